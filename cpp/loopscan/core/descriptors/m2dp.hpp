#pragma once
// M2DP adapted to VO points (paper Sec. III-B): the PCA-aligned cloud is projected on
// p x q planes, each split into azimuth x radial polar bins; a point-count matrix and a
// binarized mean-gray matrix (planes x bins) are each compressed to their first singular
// vector pair. Four versions, one per two-axis sign flip of the PCA basis.
#include "loopscan/core/config.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

struct M2dpMatrices {
  // planes x (radial * azimuth), column = ring * azimuth_bins + sector; point counts
  // (reference mode) or log(1 + count) (default mode)
  Eigen::MatrixXd count;
  Eigen::MatrixXd gray;  // same shape, binarized mean gray (0/1)
};

// Projection-plane axes, one column per plane (index p * q_count + q). Reference mode builds
// the normals in single precision like the authors' code.
void m2dp_plane_axes(const M2dpConfig& config, Eigen::Matrix3Xd& x_axes, Eigen::Matrix3Xd& y_axes);

// Count and gray matrices of an aligned cloud, already sign-flipped.
M2dpMatrices m2dp_matrices(const Cloud& aligned, const M2dpConfig& config);

// PCA alignment, four sign versions, histograms and SVD compression: 4 x 2(pq + ab) rows.
Signature m2dp_signature(const Cloud& scan, const M2dpConfig& config);

}  // namespace loopscan
