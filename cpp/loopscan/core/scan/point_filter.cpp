#include "loopscan/core/scan/point_filter.hpp"

#include <cmath>
#include <unordered_map>

#include "loopscan/core/scan/camera_points.hpp"

namespace loopscan {
namespace {

// Reference path: the authors' std::unordered_map<int, ...> with their insertion sequence, so
// its iteration order (= their output order, which their float sums depend on) is reproduced.
// `better(candidate, kept)` is strict: the first point wins ties. Points without a cell
// (`has_cell` false: outside the grid, NaN) are dropped; the authors' inputs have none.
template <typename HasCellFn, typename KeyFn, typename BetterFn>
Cloud keep_one_per_cell_reference(const Cloud& in, HasCellFn has_cell, KeyFn key_of,
                                  BetterFn better) {
  std::unordered_map<int, int> kept;
  for (int i = 0; i < static_cast<int>(in.size()); ++i) {
    if (!has_cell(in[i])) continue;
    const int key = key_of(in[i]);
    auto it = kept.find(key);
    if (it == kept.end()) {
      kept.emplace(key, i);
    } else if (better(in[i], in[it->second])) {
      it->second = i;
    }
  }
  Cloud out;
  out.reserve(kept.size());
  for (const auto& cell : kept) out.push_back(in[cell.second]);
  return out;
}

}  // namespace

Cloud cartesian_filter(const Cloud& in, double range_m, int divisions_xz, int divisions_y,
                       Mode mode) {
  ImitationConfig config;
  config.range_m = range_m;
  config.voxel_divisions_xz = divisions_xz;
  config.voxel_divisions_y = divisions_y;
  validate(config);
  // Same arithmetic as the reference: voxel = r / divisions, step = 1 / voxel.
  const double step_xz = 1.0 / (range_m / divisions_xz);
  const double step_y = 1.0 / (range_m / divisions_y);
  const int nx = static_cast<int>(std::floor(2 * range_m * step_xz) + 1);
  const int ny = static_cast<int>(std::floor(2 * range_m * step_y) + 1);
  if (mode == Mode::Reference) {
    auto key = [&](const PointI& q) {
      const int xi = static_cast<int>(std::floor((q.p.x() + range_m) * step_xz));
      const int yi = static_cast<int>(std::floor((q.p.y() + range_m) * step_y));
      const int zi = static_cast<int>(std::floor((q.p.z() + range_m) * step_xz));
      return xi + yi * nx + zi * nx * ny;
    };
    auto higher = [](const PointI& a, const PointI& b) { return -b.p.y() < -a.p.y(); };
    auto in_grid = [&](const PointI& q) { return (q.p.array().abs() < range_m).all(); };
    return keep_one_per_cell_reference(in, in_grid, key, higher);
  }
  return filter_camera_points(to_camera_points(in), ScanFilter::Cartesian, config);
}

Cloud polar_filter(const Cloud& in, double resolution_deg, Mode mode) {
  ImitationConfig config;
  config.polar_resolution_deg = resolution_deg;
  validate(config);
  const double inv = 1.0 / (resolution_deg / 180.0 * M_PI);
  const int azimuth_bins = static_cast<int>(std::floor(2 * M_PI * inv) + 1);
  if (mode == Mode::Reference) {
    auto key = [&](const PointI& q) {
      const double xz = std::sqrt(q.p.x() * q.p.x() + q.p.z() * q.p.z());
      const int azi = static_cast<int>(std::floor((std::atan2(q.p.z(), q.p.x()) + M_PI) * inv));
      const int ele = static_cast<int>(std::floor((std::atan2(q.p.y(), xz) + M_PI / 2) * inv));
      return azi + ele * azimuth_bins;
    };
    auto closer = [](const PointI& a, const PointI& b) { return b.p.norm() > a.p.norm(); };
    auto finite = [](const PointI& q) { return q.p.allFinite(); };
    return keep_one_per_cell_reference(in, finite, key, closer);
  }
  return filter_camera_points(to_camera_points(in), ScanFilter::Polar, config);
}

}  // namespace loopscan
