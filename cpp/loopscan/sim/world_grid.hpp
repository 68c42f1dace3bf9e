#pragma once
// Uniform 2D grid (x, z) over object footprints; rays walk the cells they cross (2D DDA), so a
// raycast tests only the objects near the ray instead of the whole city.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace loopscan::sim {

struct GridItem {
  Eigen::Vector4d bounds;  // (min_x, min_z, max_x, max_z)
  double top_y = 0.0;      // smallest y (highest point) of the object
  std::uint32_t code = 0;  // caller's object reference
};

class ObjectGrid {
 public:
  ObjectGrid() = default;
  ObjectGrid(const std::vector<GridItem>& items, double cell_m);

  // Calls visit(code) for the objects of each cell crossed by o + t d, 0 <= t < t_best, in ray
  // order; visit lowers t_best on a hit and the walk stops once no later cell can be nearer.
  // Cells whose objects all lie below the ray's part in the cell (y down) are skipped.
  template <class Visit>
  void traverse(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& t_best,
                Visit&& visit) const;

  // Calls visit(code) for the objects of every cell overlapping the rectangle [min, max] in
  // (x, z): an object once per such cell it lies in.
  template <class Visit>
  void visit_rect(double min_x, double min_z, double max_x, double max_z, Visit&& visit) const {
    if (nx_ == 0 || nz_ == 0) return;
    const auto cell = [&](double a, double base, int n) {
      return static_cast<int>(std::clamp(std::floor((a - base) / cell_), -1.0, double(n)));
    };
    const int i0 = std::max(cell(min_x, min_x_, nx_), 0),
              i1 = std::min(cell(max_x, min_x_, nx_), nx_ - 1);
    const int j0 = std::max(cell(min_z, min_z_, nz_), 0),
              j1 = std::min(cell(max_z, min_z_, nz_), nz_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
        for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) visit(items_[k]);
      }
  }

  int nx() const { return nx_; }
  int nz() const { return nz_; }
  double cell() const { return cell_; }
  std::size_t references() const { return items_.size(); }

 private:
  double min_x_ = 0.0, min_z_ = 0.0, cell_ = 10.0;
  int nx_ = 0, nz_ = 0;
  std::vector<std::uint32_t> start_;  // CSR offsets, size nx * nz + 1
  std::vector<std::uint32_t> items_;
  std::vector<double> top_;  // per cell: smallest top_y of its objects
};

template <class Visit>
void ObjectGrid::traverse(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& t_best,
                          Visit&& visit) const {
  if (nx_ == 0 || nz_ == 0) return;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Clip the ray to the grid rectangle.
  double t0 = 0.0, t1 = t_best;
  const double lo[2] = {min_x_, min_z_};
  const double hi[2] = {min_x_ + nx_ * cell_, min_z_ + nz_ * cell_};
  const double oo[2] = {o.x(), o.z()}, dd[2] = {d.x(), d.z()};
  for (int a = 0; a < 2; ++a) {
    if (std::abs(dd[a]) < 1e-300) {
      if (oo[a] < lo[a] || oo[a] > hi[a]) return;
      continue;
    }
    double ta = (lo[a] - oo[a]) / dd[a], tb = (hi[a] - oo[a]) / dd[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return;
  int idx[2], step[2];
  double t_next[2], t_delta[2];
  for (int a = 0; a < 2; ++a) {
    const int n = a == 0 ? nx_ : nz_;
    idx[a] =
        std::clamp(static_cast<int>(std::floor((oo[a] + t0 * dd[a] - lo[a]) / cell_)), 0, n - 1);
    if (std::abs(dd[a]) < 1e-300) {
      step[a] = 0;
      t_next[a] = t_delta[a] = kInf;
    } else {
      step[a] = dd[a] > 0 ? 1 : -1;
      const double edge = lo[a] + (idx[a] + (dd[a] > 0 ? 1 : 0)) * cell_;
      t_next[a] = (edge - oo[a]) / dd[a];
      t_delta[a] = cell_ / std::abs(dd[a]);
    }
  }
  double t_enter = t0;
  for (;;) {
    const double t_exit = std::min(t_next[0], t_next[1]);
    const std::size_t c = static_cast<std::size_t>(idx[1]) * nx_ + idx[0];
    if (start_[c] != start_[c + 1]) {
      const double te = std::min(t_exit, t_best);
      if (std::max(o.y() + t_enter * d.y(), o.y() + te * d.y()) >= top_[c]) {
        for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) visit(items_[k]);
      }
    }
    if (t_best <= t_exit || t_exit >= t1) return;
    const int a = t_next[0] < t_next[1] ? 0 : 1;
    idx[a] += step[a];
    if (idx[a] < 0 || idx[a] >= (a == 0 ? nx_ : nz_)) return;
    t_enter = t_next[a];
    t_next[a] += t_delta[a];
  }
}

}  // namespace loopscan::sim
