#include <loopscan/io/ground_truth_files.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/limits.hpp>
#include <loopscan/io/line_reader.hpp>
#include <loopscan/io/parse_numbers.hpp>

namespace loopscan::io {
namespace {

// Reads `n` finite numbers a line; returns them row after row.
std::vector<double> read_fixed_width(const std::string& path, std::size_t n,
                                     std::string_view expected) {
  LineReader reader(path);
  std::vector<double> values;
  std::string_view line;
  while (next_data_line(reader, line)) {
    Tokenizer tokens(line);
    const std::size_t first = values.size();
    values.resize(first + n);
    parse_exactly(reader, tokens, values.data() + first, n, expected, limits::kMaxCoordinateM);
    check_record_count(reader, values.size() / n, "ground-truth lines");
  }
  return values;
}

}  // namespace

GtFormat parse_gt_format(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "kitti") return GtFormat::Kitti;
  if (lower == "robotcar") return GtFormat::RobotCar;
  throw std::invalid_argument("unknown ground-truth format '" + name +
                              "' (expected 'kitti' or 'robotcar')");
}

GtFormat detect_gt_format(const std::string& path) {
  LineReader reader(path);
  std::string_view line;
  if (!next_data_line(reader, line)) throw InputError(path, 0, "at least one ground-truth line");
  Tokenizer tokens(line);
  std::size_t n = 0;
  for (std::string_view token; tokens.next(token);) ++n;
  if (n == 12) return GtFormat::Kitti;
  if (n == 3) return GtFormat::RobotCar;
  throw InputError(path, reader.line_number(),
                   "12 numbers a line (KITTI poses) or 3 (RobotCar GPS: northing easting down), "
                   "got " +
                       std::to_string(n));
}

GtFormat gt_format(const std::string& path, const std::string& name) {
  return name == "auto" ? detect_gt_format(path) : parse_gt_format(name);
}

std::vector<Eigen::Matrix<double, 3, 4>> read_kitti_poses(const std::string& path) {
  const std::vector<double> v =
      read_fixed_width(path, 12, "12 numbers: 3x4 camera-to-world pose (row-major)");
  std::vector<Eigen::Matrix<double, 3, 4>> poses(v.size() / 12);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    poses[i] = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(v.data() + 12 * i);
  }
  return poses;
}

std::vector<TumPose> read_tum_trajectory(const std::string& path) {
  LineReader reader(path);
  std::vector<TumPose> poses;
  std::string_view line;
  const char* expected = "8 numbers: timestamp tx ty tz qx qy qz qw";
  while (next_data_line(reader, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string_view::npos || line[start] == '#') continue;
    Tokenizer tokens(line);
    double v[8];
    parse_exactly(reader, tokens, v, 8, expected, 1e12);  // Unix seconds are ~1.4e9
    check_record_count(reader, poses.size(), "trajectory lines");
    if (!poses.empty() && !(v[0] > poses.back().time))
      throw InputError(path, reader.line_number(), "increasing timestamps");
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError(path, reader.line_number(), "a unit quaternion qx qy qz qw");
    TumPose p;
    p.time = v[0];
    p.T_world_body.linear() = q.normalized().toRotationMatrix();
    p.T_world_body.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    poses.push_back(p);
  }
  return poses;
}

std::vector<Eigen::Vector3d> read_positions(const std::string& path, GtFormat format) {
  std::vector<Eigen::Vector3d> positions;
  if (format == GtFormat::Kitti) {
    const auto poses = read_kitti_poses(path);
    positions.reserve(poses.size());
    for (const auto& T : poses) positions.push_back(T.col(3));
    return positions;
  }
  const std::vector<double> v = read_fixed_width(path, 3, "3 numbers: northing easting down");
  positions.reserve(v.size() / 3);
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    positions.emplace_back(v[i], v[i + 1], v[i + 2]);
  }
  return positions;
}

namespace {

// Direction of motion at row i of a position list: from the position `span_m` back to the one
// `span_m` ahead (the nearest rows that far; the row itself at either end). Zero when it has
// not moved.
Eigen::Vector3d motion_direction(const std::vector<Eigen::Vector3d>& p, std::size_t i,
                                 double span_m) {
  std::size_t a = i, b = i;
  while (a > 0 && (p[i] - p[a]).norm() < span_m) --a;
  while (b + 1 < p.size() && (p[b] - p[i]).norm() < span_m) ++b;
  const Eigen::Vector3d d = p[b] - p[a];
  return d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
}

}  // namespace

std::vector<Eigen::Vector3d> read_headings(const std::string& path, GtFormat format) {
  std::vector<Eigen::Vector3d> headings;
  if (format == GtFormat::Kitti) {
    const auto poses = read_kitti_poses(path);
    headings.reserve(poses.size());
    for (const auto& T : poses) headings.push_back(T.col(2).normalized());  // camera z: forward
    return headings;
  }
  const std::vector<Eigen::Vector3d> p = read_positions(path, format);
  headings.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) headings.push_back(motion_direction(p, i, 2.0));
  return headings;
}

}  // namespace loopscan::io
