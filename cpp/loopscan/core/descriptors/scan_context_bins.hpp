#pragma once
// Default-mode Scan Context of several centres (the place and its lateral versions) from one
// read of the aligned points: every point's bin for every centre is found a vector at a time
// (offsets in double, then radius and the tangent of the angle in single precision; lanes
// within a wide margin of a ring or sector boundary get their bin from the doubles through
// AngleBinner, exact), then accumulated in point order: the rows of the per-centre loop in
// scan_context.cpp, bit for bit.
#include <vector>

#include <Eigen/Core>

#include "loopscan/core/config.hpp"
#include "loopscan/core/types.hpp"

namespace loopscan {

// Whether scan_context_rows handles this config (default mode, sectors a multiple of 4, up to
// 128 sectors); callers fall back to binning centre by centre otherwise.
bool scan_context_rows_usable(const ScanContextConfig& config);

// out.row(v) = [structure | intensity] of the aligned cloud binned around centres[v] (aligned
// axes 1 and 2), gray mean `mean`. out must be centres.size() x 2 * rings * sectors.
void scan_context_rows(const Cloud& aligned, const ScanContextConfig& config,
                       const std::vector<Eigen::Vector2d>& centres, double mean,
                       Eigen::MatrixXd& out);

// The same from the scan itself, aligned on the fly (no aligned copy): frame.axes * (p -
// frame.centre), as align_scan; the gray mean summed as cloud_gray_mean. For axes whose
// entries are 0 and +-1 (camera and centroid frames) every product is exact, so the points
// equal align_scan's whatever the compiler fuses.
struct AlignFrame {
  Eigen::Matrix3d axes;
  Eigen::Vector3d centre;
};
void scan_context_rows(const Cloud& scan, const AlignFrame& frame, const ScanContextConfig& config,
                       const std::vector<Eigen::Vector2d>& centres, Eigen::MatrixXd& out);

}  // namespace loopscan
