#include "loopscan/sim/world_grid.hpp"

namespace loopscan::sim {

ObjectGrid::ObjectGrid(const std::vector<GridItem>& items, double cell_m) : cell_(cell_m) {
  if (items.empty()) return;
  double max_x = -1e300, max_z = -1e300;
  min_x_ = min_z_ = 1e300;
  for (const auto& it : items) {
    min_x_ = std::min(min_x_, it.bounds[0]);
    min_z_ = std::min(min_z_, it.bounds[1]);
    max_x = std::max(max_x, it.bounds[2]);
    max_z = std::max(max_z, it.bounds[3]);
  }
  nx_ = static_cast<int>(std::floor((max_x - min_x_) / cell_)) + 1;
  nz_ = static_cast<int>(std::floor((max_z - min_z_) / cell_)) + 1;
  const std::size_t cells = static_cast<std::size_t>(nx_) * nz_;
  const auto range = [&](double a, double base, int n) {
    return std::clamp(static_cast<int>(std::floor((a - base) / cell_)), 0, n - 1);
  };
  std::vector<std::uint32_t> count(cells + 1, 0);
  top_.assign(cells, std::numeric_limits<double>::infinity());
  // Count, then fill: the CSR lists keep the items' order, so traversal order is deterministic.
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      start_.assign(cells + 1, 0);
      for (std::size_t c = 1; c <= cells; ++c) start_[c] = start_[c - 1] + count[c - 1];
      items_.assign(start_.back(), 0);
      std::fill(count.begin(), count.end(), 0);
    }
    for (const auto& it : items) {
      const int i0 = range(it.bounds[0], min_x_, nx_), i1 = range(it.bounds[2], min_x_, nx_);
      const int j0 = range(it.bounds[1], min_z_, nz_), j1 = range(it.bounds[3], min_z_, nz_);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
          if (pass == 1) {
            items_[start_[c] + count[c]] = it.code;
            top_[c] = std::min(top_[c], it.top_y);
          }
          ++count[c];
        }
    }
  }
}

}  // namespace loopscan::sim
