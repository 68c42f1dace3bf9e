#pragma once
// Default-mode M2DP matrices from the packed sums (m2dp.cpp), in one contiguous pass.
#include <cstddef>
#include <vector>

#include "loopscan/core/descriptors/m2dp.hpp"

namespace loopscan {

// log1p(k) for k = 0 .. n - 1 (std::log1p, the same values), n up to 2^16: a table kept per
// thread and grown on demand.
const std::vector<double>& log1p_table(std::size_t n);

// The default-mode matrices (planes x bins) from packed sums laid out like them (column-major:
// bin-major, acc[b * planes + k]), count = v >> shift, gray sum = (v & (2^shift - 1)) * unit:
// log1p(count) and (count > 0 && gray sum / count > mean), the values finish() in m2dp.cpp
// makes from the unpacked counts and sums. `max_count` bounds every count; below 2^16.
M2dpMatrices finish_packed(const std::vector<long long>& acc, int shift, double unit,
                           Eigen::Index planes, Eigen::Index bins, double mean,
                           std::size_t max_count);

}  // namespace loopscan
