#include "loopscan/closure/voxel_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace loopscan::closure {
namespace {

// 21 bits a coordinate: +-2^20 voxels, beyond any range validate() admits (farther cells are
// clamped to the border, before the cast, so that no value overflows).
std::uint64_t voxel_key(const Eigen::Vector3f& p, double inv_voxel) {
  const auto cell = [&](float v) {
    const double c = std::clamp(std::floor(v * inv_voxel), -1048576.0, 1048575.0);
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(c) + 1048576);
  };
  return (cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z());
}

}  // namespace

void validate(const CloudConfig& c) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("cloud config: " + what);
  };
  if (!(c.voxel_m >= 0.01 && c.voxel_m <= 10.0)) fail("voxel_m must be in [0.01, 10]");
  if (c.max_points < 16 || c.max_points > (1 << 22)) fail("max_points must be in [16, 2^22]");
  if (!(c.max_range_m > 0 && c.max_range_m <= 1000)) fail("max_range_m must be in (0, 1000]");
  if (c.max_range_m / c.voxel_m >= double(1 << 19)) fail("max_range_m / voxel_m too large");
  if (c.max_unclassified_places < 0 || c.max_unclassified_places > (1 << 24)) {
    fail("max_unclassified_places must be in [0, 2^24]");
  }
}

Points3f voxel_downsample(const Points3f& points, double voxel_m) {
  // Open addressing on the voxel key; voxels come out in the order of their first point.
  const double inv = 1.0 / voxel_m;
  std::size_t capacity = 16;
  while (capacity < 2 * points.size()) capacity *= 2;
  constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  std::vector<std::uint64_t> keys(capacity, kEmpty);
  std::vector<std::uint32_t> slot_voxel(capacity);
  std::vector<Eigen::Vector3d> sums;
  std::vector<std::uint32_t> counts;
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    const std::uint64_t key = voxel_key(p, inv);
    std::size_t h = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & (capacity - 1);
    while (keys[h] != kEmpty && keys[h] != key) h = (h + 1) & (capacity - 1);
    if (keys[h] == kEmpty) {
      keys[h] = key;
      slot_voxel[h] = static_cast<std::uint32_t>(sums.size());
      sums.push_back(Eigen::Vector3d::Zero());
      counts.push_back(0);
    }
    sums[slot_voxel[h]] += p.cast<double>();
    ++counts[slot_voxel[h]];
  }
  Points3f out(sums.size());
  for (std::size_t i = 0; i < sums.size(); ++i) out[i] = (sums[i] / double(counts[i])).cast<float>();
  return out;
}

Points3f voxel_cloud(const Points3f& scan, const CloudConfig& config) {
  validate(config);
  const float r2 = static_cast<float>(config.max_range_m * config.max_range_m);
  Points3f near;
  near.reserve(scan.size());
  for (const Eigen::Vector3f& p : scan) {
    if (p.allFinite() && p.squaredNorm() <= r2) near.push_back(p);
  }
  Points3f cloud = voxel_downsample(near, config.voxel_m);
  const std::size_t cap = static_cast<std::size_t>(config.max_points);
  if (cloud.size() <= cap) return cloud;
  Points3f kept;
  kept.reserve(cap);
  for (std::size_t i = 0; i < cap; ++i) kept.push_back(cloud[i * cloud.size() / cap]);
  return kept;
}

Points3f every_nth(const Points3f& points, std::size_t stride) {
  stride = std::max<std::size_t>(stride, 1);
  Points3f out;
  out.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
  return out;
}

}  // namespace loopscan::closure
