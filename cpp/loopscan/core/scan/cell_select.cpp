#include "loopscan/core/scan/cell_select.hpp"

#include <algorithm>
#include <cstring>

namespace loopscan {
namespace {

struct Cell {
  std::uint32_t stamp;  // generation of the last call that touched the cell
  std::int32_t best;    // kept point index
  double score;
};

// Half the size, for float scores and fewer than 2^24 points: the Cartesian table has ~450k
// cells, so its footprint (L3 or memory) is what a call waits for.
struct SmallCell {
  float score;
  std::uint32_t tag;  // stamp << 24 | kept point index
};

// The cell a few points ahead is requested early (keys above max_key clamped to a valid one).
constexpr std::size_t kAhead = 24;

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
    if (i + kAhead < n) __builtin_prefetch(&cells[std::min(keys[i + kAhead], max_key)], 1);
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

void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<float>& scores,
                   std::uint32_t max_key, std::vector<int>& kept) {
  const std::size_t n = keys.size();
  if (n >= (std::size_t{1} << 24)) {  // indices need more than 24 bits: the wide cells
    best_per_cell(keys, std::vector<double>(scores.begin(), scores.end()), max_key, kept);
    return;
  }
  thread_local std::vector<SmallCell> cells;
  thread_local std::vector<std::uint32_t> touched;
  thread_local std::uint32_t generation = 0;
  if (cells.size() < static_cast<std::size_t>(max_key) + 1)
    cells.resize(std::size_t(max_key) + 1, {0.f, 0});
  if (++generation == 256) {  // 8-bit stamps wrapped: forget every stamp
    for (SmallCell& c : cells) c.tag = 0;
    generation = 1;
  }
  const std::uint32_t stamp = generation << 24;
  touched.resize(n);
  std::size_t n_touched = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) __builtin_prefetch(&cells[std::min(keys[i + kAhead], max_key)], 1);
    if (keys[i] > max_key) continue;
    SmallCell& c = cells[keys[i]];
    const bool fresh = (c.tag & 0xff000000u) != stamp;
    const bool better = fresh | (scores[i] < c.score);
    // Selects by masks: compilers turn the ?: forms into branches, mispredicted half the time.
    const std::uint32_t m = 0u - static_cast<std::uint32_t>(better);
    c.tag = (c.tag & ~m) | ((stamp | static_cast<std::uint32_t>(i)) & m);
    std::uint32_t old_bits, new_bits;
    std::memcpy(&old_bits, &c.score, 4);
    std::memcpy(&new_bits, &scores[i], 4);
    const std::uint32_t bits = (old_bits & ~m) | (new_bits & m);
    std::memcpy(&c.score, &bits, 4);
    touched[n_touched] = keys[i];
    n_touched += fresh;
  }
  kept.resize(n_touched);
  for (std::size_t k = 0; k < n_touched; ++k) kept[k] = cells[touched[k]].tag & 0xffffffu;
}

}  // namespace loopscan
