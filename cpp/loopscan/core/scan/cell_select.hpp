#pragma once
// Keeps, per cell key, the index of the point with the smallest score (the first on ties), with
// cells in order of first occurrence. A dense per-cell table with generation stamps and
// branch-free updates: no hashing, no sorting, no unpredictable branches. Keys above max_key
// belong to no cell and are skipped.
#include <cstdint>
#include <vector>

namespace loopscan {

void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<double>& scores,
                   std::uint32_t max_key, std::vector<int>& kept);
// The same for float scores, with cells half the size (the same result).
void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<float>& scores,
                   std::uint32_t max_key, std::vector<int>& kept);

}  // namespace loopscan
