#pragma once
// DELIGHT adapted to VO points (paper Sec. III-B): 16 regions of the PCA-aligned cloud (inner
// sphere of radius r_in around the centroid or outside it, x the 8 octants) and a 256-bin gray
// histogram (raw counts) per region.
#include "loopscan/core/config.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

// Region of an aligned point: 8 * (|a| > r_in) + 4 * (a2 > 0) + 2 * (a1 > 0) + (a0 > 0).
int delight_region(const Eigen::Vector3d& aligned, const DelightConfig& config);

// 16 x bins histogram of an already aligned cloud.
Signature delight_of_aligned(const Cloud& aligned, const DelightConfig& config);

// PCA alignment + histograms.
Signature delight_signature(const Cloud& scan, const DelightConfig& config);

}  // namespace loopscan
