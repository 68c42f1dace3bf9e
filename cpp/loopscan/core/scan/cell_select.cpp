#include "loopscan/core/scan/cell_select.hpp"

namespace loopscan {
namespace {

struct Cell {
  std::uint32_t stamp;  // generation of the last call that touched the cell
  std::int32_t best;    // kept point index
  double score;
};

}  // namespace

void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<double>& scores,
                   std::uint32_t max_key, std::vector<int>& kept) {
  thread_local std::vector<Cell> cells;
  thread_local std::vector<std::uint32_t> touched;
  thread_local std::uint32_t generation = 0;
  if (cells.size() < static_cast<std::size_t>(max_key) + 1)
    cells.resize(std::size_t(max_key) + 1, {0, 0, 0});
  if (++generation == 0) {  // wrapped: forget every stamp
    for (Cell& c : cells) c.stamp = 0;
    generation = 1;
  }
  const std::size_t n = keys.size();
  touched.resize(n);
  std::size_t n_touched = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (keys[i] > max_key) continue;  // no cell: a point the caller marked as outside
    Cell& c = cells[keys[i]];
    const bool fresh = c.stamp != generation;
    const bool better = fresh || scores[i] < c.score;
    c.best = better ? static_cast<std::int32_t>(i) : c.best;
    c.score = better ? scores[i] : c.score;
    c.stamp = generation;
    touched[n_touched] = keys[i];
    n_touched += fresh;
  }
  kept.resize(n_touched);
  for (std::size_t k = 0; k < n_touched; ++k) kept[k] = cells[touched[k]].best;
}

}  // namespace loopscan
