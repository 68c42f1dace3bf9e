#pragma once
// Scan Context adapted to VO points (paper Sec. III-B): PCA-aligned cloud, rings x sectors
// polar bins on the horizontal plane; structure = height RANGE per bin, intensity = 1 where the
// bin's mean gray value exceeds the cloud's mean.
#include "loopscan/core/config.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

struct ScanContext {
  Eigen::VectorXd structure;  // sectors * rings, index = sector * rings + ring
  Eigen::VectorXd intensity;  // same layout, 0/1
};

// Bins an already PCA-aligned cloud (axis 0 = up). Reference mode keeps the authors' flat
// index leak (a point beyond the last ring lands in the next sector's inner rings).
ScanContext scan_context_of_aligned(const Cloud& aligned, const ScanContextConfig& config);

// Alignment (the config's frame) + binning; 1 x 2*sectors*rings signature row, and one more per
// lateral version (ScanContextConfig): the same aligned points binned around a centre moved
// that far to the side. `frame` (optional): the aligned axes in the scan's frame (see pca_align).
Signature scan_context_signature(const Cloud& scan, const ScanContextConfig& config,
                                 Eigen::Matrix3d* frame = nullptr);

}  // namespace loopscan
