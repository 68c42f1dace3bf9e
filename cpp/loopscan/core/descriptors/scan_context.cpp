#include "loopscan/core/descriptors/scan_context.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/core/descriptors/fast_angle.hpp"
#include "loopscan/core/descriptors/gray_mean.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"

namespace loopscan {

ScanContext scan_context_of_aligned(const Cloud& aligned, const ScanContextConfig& config) {
  const int rings = config.rings, sectors = config.sectors, bins = rings * sectors;
  const bool reference = config.mode == Mode::Reference;
  const double sector_inv = sectors / (2.0 * M_PI);
  const double ring_inv = rings / config.max_radius_m;
  const AngleBinner sector_of(sector_inv, M_PI);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(bins), low = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXd high = Eigen::VectorXd::Zero(bins), gray = Eigen::VectorXd::Zero(bins);
  for (const PointI& q : aligned) {
    const double a1 = q.p(1), a2 = q.p(2);
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
  const double mean = cloud_gray_mean(aligned, config.mode);
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

Signature scan_context_signature(const Cloud& scan, const ScanContextConfig& config,
                                 Eigen::Matrix3d* frame) {
  validate(config);
  const int versions = 1 + static_cast<int>(config.lateral_versions_m.size());
  Signature rows(versions, 2 * config.rings * config.sectors);
  for (int v = 0; v < versions; ++v) {
    const double offset = config.lateral_offset_m + (v > 0 ? config.lateral_versions_m[v - 1] : 0);
    const ScanContext sc = scan_context_of_aligned(
        align_scan(scan, config.frame, config.mode, v == 0 ? frame : nullptr, offset), config);
    rows.row(v) << sc.structure.transpose(), sc.intensity.transpose();
  }
  return rows;
}

}  // namespace loopscan
