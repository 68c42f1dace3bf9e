#pragma once
// PCA alignment shared by all descriptors (paper Sec. III-B): center on the centroid and
// express points in the eigenvector basis ordered by ascending eigenvalue, so axis 0 (least
// variance) is taken as "up" and axes 1, 2 span the horizontal plane.
#include "loopscan/core/config.hpp"

namespace loopscan {

// Reference mode uses the authors' exact Eigen path (dynamic-size solver), so eigenvector
// signs match theirs. Default mode uses the fixed-size solver and makes the basis
// right-handed: the descriptors' sign "versions" (two-axis flips) then cover every pair.
// An empty input gives an empty output. `to_aligned` (optional) receives the matrix whose rows
// are the aligned axes in the input frame (identity for an empty input), which turns a
// descriptor's sector alignment back into a yaw of the keyframe.
Cloud pca_align(const Cloud& cloud, Mode mode, Eigen::Matrix3d* to_aligned = nullptr);

// The scan in a descriptor's frame (see DescriptorFrame); reference mode is always pca_align.
// `to_aligned` as for pca_align. `lateral_offset_m` (camera frame only) centres the descriptor
// that far along the camera's x axis (right): where a car in the next lane would be.
Cloud align_scan(const Cloud& cloud, DescriptorFrame frame, Mode mode,
                 Eigen::Matrix3d* to_aligned = nullptr, double lateral_offset_m = 0.0);
// The same into `out`, whose memory is reused (a scan's copy is ~170 KB: a fresh one costs
// page faults every call).
void align_scan(const Cloud& cloud, DescriptorFrame frame, Mode mode, Cloud& out,
                Eigen::Matrix3d* to_aligned = nullptr, double lateral_offset_m = 0.0);

// Default mode, frames other than Pca: the aligned axes (rows) and the centre, so that a point
// aligned is axes * (p - centre), as align_scan computes it. Throws like align_scan.
Eigen::Matrix3d scan_axes(const Cloud& cloud, DescriptorFrame frame, Eigen::Vector3d* centre,
                          double lateral_offset_m = 0.0);

}  // namespace loopscan
