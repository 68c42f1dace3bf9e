#include "loopscan/core/descriptors/delight.hpp"

#include <algorithm>

#include "loopscan/core/descriptors/pca_align.hpp"

namespace loopscan {

int delight_region(const Eigen::Vector3d& a, const DelightConfig& config) {
  if (config.mode == Mode::Reference) {
    // The authors' code compares single-precision copies of the coordinates and the norm.
    const float x = a(0), y = a(1), z = a(2), d = a.norm();
    return 8 * (d > config.inner_radius_m) + 4 * (z > 0) + 2 * (y > 0) + (x > 0);
  }
  return 8 * (a.norm() > config.inner_radius_m) + 4 * (a(2) > 0) + 2 * (a(1) > 0) + (a(0) > 0);
}

Signature delight_of_aligned(const Cloud& aligned, const DelightConfig& config) {
  Signature hist = Signature::Zero(16, config.intensity_bins);
  for (const PointI& q : aligned) {
    // std::clamp(int(g), 0, bins - 1) for every finite g, and NaN -> 0, inf -> bins - 1
    // without the undefined conversion.
    const float g = q.intensity;
    const int bin =
        g >= 0 ? (g < config.intensity_bins ? static_cast<int>(g) : config.intensity_bins - 1) : 0;
    hist(delight_region(q.p, config), bin) += 1;
  }
  return hist;
}

Signature delight_signature(const Cloud& scan, const DelightConfig& config) {
  validate(config);
  return delight_of_aligned(align_scan(scan, config.frame, config.mode), config);
}

}  // namespace loopscan
