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

std::vector<Eigen::Matrix<double, 3, 4>> read_kitti_poses(const std::string& path) {
  const std::vector<double> v =
      read_fixed_width(path, 12, "12 numbers: 3x4 camera-to-world pose (row-major)");
  std::vector<Eigen::Matrix<double, 3, 4>> poses(v.size() / 12);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    poses[i] = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(v.data() + 12 * i);
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

}  // namespace loopscan::io
