#pragma once
// Keeps, per cell key, the index of the point with the smallest score (the first on ties),
// output ordered by key. A stable two-pass radix sort and one scan: no hashing, no
// unpredictable branches, which is what the default-mode filters need for ~16k points a scan.
#include <cstdint>
#include <vector>

namespace loopscan {

void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<double>& scores,
                   std::uint32_t max_key, std::vector<int>& kept);

}  // namespace loopscan
