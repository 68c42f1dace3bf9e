#include "loopscan/core/descriptors/scan_context.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/core/descriptors/fast_angle.hpp"
#include "loopscan/core/descriptors/gray_mean.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/descriptors/scan_context_bins.hpp"

namespace loopscan {

namespace {

// Bins the aligned cloud around the horizontal point `centre` (aligned axes 1 and 2; a lateral
// version's centre) with the cloud's gray mean `mean` (the same for every version).
ScanContext bin_aligned(const Cloud& aligned, const ScanContextConfig& config,
                        const Eigen::Vector2d& centre, double mean) {
  const int rings = config.rings, sectors = config.sectors, bins = rings * sectors;
  const bool reference = config.mode == Mode::Reference;
  const double sector_inv = sectors / (2.0 * M_PI);
  const double ring_inv = rings / config.max_radius_m;
  const AngleBinner sector_of(sector_inv, M_PI);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(bins), low = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXd high = Eigen::VectorXd::Zero(bins), gray = Eigen::VectorXd::Zero(bins);
  for (const PointI& q : aligned) {
    const double a1 = q.p(1) - centre.x(), a2 = q.p(2) - centre.y();
    int sector, ring = static_cast<int>(std::floor(std::sqrt(a1 * a1 + a2 * a2) * ring_inv));
    if (reference) {
      sector = static_cast<int>(std::floor((std::atan2(a2, a1) + M_PI) * sector_inv));
    } else {
      if (ring >= rings) continue;           // beyond max radius: dropped, not leaked
      sector = sector_of(a2, a1) % sectors;  // +pi and -pi: the same ray
    }
    const int idx = sector * rings + ring;
    if (idx >= bins) continue;
    const double h = q.p(0);
    if (count(idx) == 0) {
      low(idx) = high(idx) = h;
      gray(idx) = q.intensity;
    } else {
      low(idx) = std::min(low(idx), h);
      high(idx) = std::max(high(idx), h);
      gray(idx) += q.intensity;
    }
    count(idx) += 1;
  }
  for (int i = 0; i < bins; ++i) {
    if (count(i) > 0) gray(i) = gray(i) / count(i) > mean ? 1.0 : 0.0;
  }
  if (config.max_height) {
    for (int i = 0; i < bins; ++i) {
      high(i) = count(i) > 0 ? std::max(0.0, high(i) + config.sensor_height_m) : 0.0;
    }
    return {high, gray};
  }
  return {high - low, gray};
}

}  // namespace

ScanContext scan_context_of_aligned(const Cloud& aligned, const ScanContextConfig& config) {
  return bin_aligned(aligned, config, Eigen::Vector2d::Zero(),
                     cloud_gray_mean(aligned, config.mode));
}

namespace {

// Centres of the place and its lateral versions in the aligned plane (axes 1, 2).
std::vector<Eigen::Vector2d> version_centres(const ScanContextConfig& config,
                                             const Eigen::Matrix3d& axes) {
  std::vector<Eigen::Vector2d> centres;
  for (std::size_t v = 0; v <= config.lateral_versions_m.size(); ++v) {
    const double offset = v > 0 ? config.lateral_versions_m[v - 1] : 0.0;
    const Eigen::Vector3d side = axes * Eigen::Vector3d(offset, 0, 0);  // camera x: right
    centres.push_back(side.tail<2>());
  }
  return centres;
}

}  // namespace

Signature scan_context_signature(const Cloud& scan, const ScanContextConfig& config,
                                 Eigen::Matrix3d* frame) {
  validate(config);
  const Eigen::Index versions = 1 + static_cast<Eigen::Index>(config.lateral_versions_m.size());
  Signature rows(versions, 2 * config.rings * config.sectors);
  const bool fast = scan_context_rows_usable(config);
  if (fast &&
      (config.frame == DescriptorFrame::Camera || config.frame == DescriptorFrame::Centroid)) {
    // Axes of 0 and +-1: the points are aligned on the fly, exactly as align_scan would.
    AlignFrame f;
    f.axes = scan_axes(scan, config.frame, &f.centre, config.lateral_offset_m);
    if (frame) *frame = f.axes;
    scan_context_rows(scan, f, config, version_centres(config, f.axes), rows);
    return rows;
  }
  // Aligned once; a lateral version bins the same points around a centre moved to its side.
  Eigen::Matrix3d axes;
  thread_local Cloud aligned;
  align_scan(scan, config.frame, config.mode, aligned, &axes, config.lateral_offset_m);
  if (frame) *frame = axes;
  const double mean = cloud_gray_mean(aligned, config.mode);
  const std::vector<Eigen::Vector2d> centres = version_centres(config, axes);
  if (fast) {  // every version from one pass over the points
    scan_context_rows(aligned, config, centres, mean, rows);
    return rows;
  }
  for (Eigen::Index v = 0; v < versions; ++v) {
    const ScanContext sc = bin_aligned(aligned, config, centres[v], mean);
    rows.row(v) << sc.structure.transpose(), sc.intensity.transpose();
  }
  return rows;
}

}  // namespace loopscan
