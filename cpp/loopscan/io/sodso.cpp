#include <loopscan/io/sodso.hpp>

#include <cmath>
#include <string_view>

#include <Eigen/Core>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/limits.hpp>
#include <loopscan/io/line_reader.hpp>
#include <loopscan/io/parse_numbers.hpp>

namespace loopscan::io {
namespace {

constexpr std::string_view kPoseExpected =
    "13 numbers: integer keyframe id and 3x4 world-to-camera pose (row-major)";
constexpr const char* kPointExpected = "5 numbers: id x y z intensity";

// Reads the leading integer id of a record; the caller's message describes the full line.
int read_id(const LineReader& reader, Tokenizer& tokens, std::string_view expected) {
  std::string_view token;
  int id = 0;
  if (!tokens.next(token) || !parse_number(token, id)) {
    throw InputError(reader.path(), reader.line_number(), std::string(expected));
  }
  if (id < 0) throw InputError(reader.path(), reader.line_number(), "a non-negative keyframe id");
  return id;
}

}  // namespace

std::vector<KeyframePose> read_sodso_poses(const std::string& path) {
  LineReader reader(path);
  std::vector<KeyframePose> poses;
  std::string_view line;
  double v[12];
  while (next_data_line(reader, line)) {
    Tokenizer tokens(line);
    KeyframePose pose;
    pose.id = read_id(reader, tokens, kPoseExpected);
    parse_exactly(reader, tokens, v, 12, kPoseExpected, limits::kMaxCoordinateM);
    if (!poses.empty() && pose.id <= poses.back().id) {
      throw InputError(path, reader.line_number(), "keyframe ids in increasing order");
    }
    pose.T_cam_world = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(v);
    poses.push_back(pose);
    check_record_count(reader, poses.size(), "poses");
  }
  return poses;
}

SodsoPointReader::SodsoPointReader(const std::string& path)
    : reader_(std::make_unique<LineReader>(path)) {}
SodsoPointReader::~SodsoPointReader() = default;
SodsoPointReader::SodsoPointReader(SodsoPointReader&&) noexcept = default;
SodsoPointReader& SodsoPointReader::operator=(SodsoPointReader&&) noexcept = default;

bool SodsoPointReader::next(IdPoint& point) {
  if (ahead_) {
    point = *ahead_;
    ahead_.reset();
    return true;
  }
  LineReader& reader = *reader_;
  std::string_view line;
  std::string_view token;
  double xyz[3];
  while (next_data_line(reader, line)) {
    Tokenizer tokens(line);
    const int id = read_id(reader, tokens, kPointExpected);
    float intensity = 0.f;
    for (double& c : xyz) {
      if (!tokens.next(token) || !parse_number(token, c)) {
        throw InputError(reader.path(), reader.line_number(), kPointExpected);
      }
    }
    // Parsed as float, not double-then-cast, to round exactly like the reference `>> float`.
    if (!tokens.next(token) || !parse_number(token, intensity) || !tokens.at_end()) {
      throw InputError(reader.path(), reader.line_number(), kPointExpected);
    }
    if (id < last_id_) {
      throw InputError(reader.path(), reader.line_number(), "point ids in non-decreasing order");
    }
    last_id_ = id;
    const auto usable = [](double c) { return std::abs(c) <= limits::kMaxCoordinateM; };
    if (!usable(xyz[0]) || !usable(xyz[1]) || !usable(xyz[2]) || !std::isfinite(intensity)) {
      ++stats_.non_finite_skipped;
      continue;
    }
    if (intensity < 0.f || intensity > 255.f) {
      intensity = intensity < 0.f ? 0.f : 255.f;
      ++stats_.intensity_clamped;
    }
    point.id = id;
    point.p_world = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    point.intensity = intensity;
    check_record_count(reader, ++count_, "points");
    return true;
  }
  return false;
}

void SodsoPointReader::read_until(int last_id, std::vector<IdPoint>& out) {
  out.clear();
  IdPoint point;
  while (next(point)) {
    if (point.id > last_id) {
      ahead_ = point;
      return;
    }
    out.push_back(point);
  }
}

std::vector<IdPoint> read_sodso_points(const std::string& path, PointReadStats* stats) {
  SodsoPointReader reader(path);
  std::vector<IdPoint> points;
  IdPoint point;
  while (reader.next(point)) points.push_back(point);
  if (stats != nullptr) *stats = reader.stats();
  return points;
}

}  // namespace loopscan::io
