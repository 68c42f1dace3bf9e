#include "loopscan/core/point_filter.hpp"

#include <cmath>
#include <unordered_map>

#include "loopscan/core/cell_table.hpp"
#include "loopscan/core/fast_angle.hpp"

namespace loopscan {
namespace {

// Keeps one point per cell. `better(candidate, kept)` decides replacement (strict: the first
// point wins ties). Reference mode goes through std::unordered_map<int, ...> with the same
// insertion sequence as the authors' code, so iteration (= output) order matches theirs.
template <typename KeyFn, typename BetterFn>
Cloud keep_one_per_cell(const Cloud& in, Mode mode, KeyFn key_of, BetterFn better) {
  Cloud out;
  if (mode == Mode::Reference) {
    std::unordered_map<int, int> kept;
    for (int i = 0; i < static_cast<int>(in.size()); ++i) {
      const int key = static_cast<int>(key_of(in[i]));
      auto it = kept.find(key);
      if (it == kept.end()) {
        kept.emplace(key, i);
      } else if (better(in[i], in[it->second])) {
        it->second = i;
      }
    }
    out.reserve(kept.size());
    for (const auto& cell : kept) out.push_back(in[cell.second]);
    return out;
  }
  thread_local CellTable table;
  table.reset(in.size());
  for (int i = 0; i < static_cast<int>(in.size()); ++i) {
    bool inserted = false;
    int& kept = table.find_or_insert(key_of(in[i]), i, inserted);
    if (!inserted && better(in[i], in[kept])) kept = i;
  }
  out.reserve(table.kept().size());
  for (int i : table.kept()) out.push_back(in[i]);
  return out;
}

}  // namespace

Cloud cartesian_filter(const Cloud& in, double range_m, int divisions_xz, int divisions_y,
                       Mode mode) {
  // Same arithmetic as the reference: voxel = r / divisions, step = 1 / voxel.
  const double step_xz = 1.0 / (range_m / divisions_xz);
  const double step_y = 1.0 / (range_m / divisions_y);
  const std::int64_t nx = static_cast<std::int64_t>(std::floor(2 * range_m * step_xz) + 1);
  const std::int64_t ny = static_cast<std::int64_t>(std::floor(2 * range_m * step_y) + 1);
  auto key = [&](const PointI& q) -> std::int64_t {
    const auto xi = static_cast<std::int64_t>(std::floor((q.p.x() + range_m) * step_xz));
    const auto yi = static_cast<std::int64_t>(std::floor((q.p.y() + range_m) * step_y));
    const auto zi = static_cast<std::int64_t>(std::floor((q.p.z() + range_m) * step_xz));
    return xi + yi * nx + zi * nx * ny;
  };
  // In range, |coordinate| < r, so the shifted values are positive and truncation is floor.
  auto fast_key = [&](const PointI& q) -> std::int64_t {
    const auto xi = static_cast<std::int64_t>((q.p.x() + range_m) * step_xz);
    const auto yi = static_cast<std::int64_t>((q.p.y() + range_m) * step_y);
    const auto zi = static_cast<std::int64_t>((q.p.z() + range_m) * step_xz);
    return xi + yi * nx + zi * nx * ny;
  };
  auto higher = [](const PointI& a, const PointI& b) { return -b.p.y() < -a.p.y(); };
  if (mode == Mode::Reference) return keep_one_per_cell(in, mode, key, higher);
  return keep_one_per_cell(in, mode, fast_key, higher);
}

Cloud polar_filter(const Cloud& in, double resolution_deg, Mode mode) {
  const double inv = 1.0 / (resolution_deg / 180.0 * M_PI);
  const std::int64_t azimuth_bins = static_cast<std::int64_t>(std::floor(2 * M_PI * inv) + 1);
  if (mode == Mode::Reference) {
    auto key = [&](const PointI& q) -> std::int64_t {
      const double xz = std::sqrt(q.p.x() * q.p.x() + q.p.z() * q.p.z());
      const auto azi = static_cast<std::int64_t>(std::floor((std::atan2(q.p.z(), q.p.x()) + M_PI) * inv));
      const auto ele = static_cast<std::int64_t>(std::floor((std::atan2(q.p.y(), xz) + M_PI / 2) * inv));
      return azi + ele * azimuth_bins;
    };
    auto closer = [](const PointI& a, const PointI& b) { return b.p.norm() > a.p.norm(); };
    return keep_one_per_cell(in, mode, key, closer);
  }
  auto key = [&](const PointI& q) -> std::int64_t {
    const double xz = std::sqrt(q.p.x() * q.p.x() + q.p.z() * q.p.z());
    const std::int64_t azi = angle_bin(q.p.z(), q.p.x(), M_PI, inv);
    const std::int64_t ele = angle_bin(q.p.y(), xz, M_PI / 2, inv);
    return azi + ele * azimuth_bins;
  };
  auto closer = [](const PointI& a, const PointI& b) {
    return b.p.squaredNorm() > a.p.squaredNorm();
  };
  return keep_one_per_cell(in, mode, key, closer);
}

}  // namespace loopscan
