// key_scan::scan_nearest: a pilot scan over a strided sample of the blocks sets the bound.
#include <algorithm>
#include <vector>

#include "loopscan/core/database/key_scan_kernels.hpp"
#include "loopscan/core/database/nearest_set.hpp"

namespace loopscan::key_scan {
namespace {

constexpr std::size_t kStride = 8;
// Below this many places per sought one the pilot's bound would be loose anyway.
constexpr std::size_t kMinPlacesPerCount = 16;

}  // namespace

void scan_nearest(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                  const std::uint32_t* queries, int n_queries, std::size_t count, Nearest* sinks) {
  if (count == 0 || n_blocks * kBlock < kMinPlacesPerCount * count) {
    scan(blocks, n_blocks, pairs, queries, n_queries, sinks);
    return;
  }
  // The sample holds 1/8 of the places: its (count / 4)-th distance is about the full set's
  // (2 count)-th.
  std::vector<BlockRef> sample;
  for (std::size_t b = 0; b < n_blocks; b += kStride) sample.push_back(blocks[b]);
  const std::size_t pilot_count = std::max<std::size_t>(1, 2 * count / kStride);
  std::vector<Nearest> pilots;
  pilots.reserve(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) pilots.emplace_back(pilot_count, sinks[v].eligible());
  scan(sample.data(), sample.size(), pairs, queries, n_queries, pilots.data());
  std::vector<bool> bounded(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) {
    bounded[v] = pilots[v].full();
    if (bounded[v]) sinks[v].tighten(pilots[v].bound());
  }
  scan(blocks, n_blocks, pairs, queries, n_queries, sinks);
  for (int v = 0; v < n_queries; ++v) {
    if (!bounded[v] || sinks[v].size() >= count) continue;
    sinks[v] = Nearest(count, sinks[v].eligible());
    scan(blocks, n_blocks, pairs, queries + static_cast<std::size_t>(v) * pairs, 1, &sinks[v]);
  }
}

}  // namespace loopscan::key_scan
