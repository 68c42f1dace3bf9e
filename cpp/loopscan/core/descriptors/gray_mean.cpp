#include "loopscan/core/descriptors/gray_mean.hpp"

namespace loopscan {

double cloud_gray_mean(const Cloud& cloud, Mode mode) {
  if (cloud.empty()) return 0.0;
  if (mode == Mode::Reference) {
    float sum = 0.f;
    for (const PointI& q : cloud) sum += q.intensity;
    return sum / cloud.size();
  }
  double sum = 0.0;
  for (const PointI& q : cloud) sum += q.intensity;
  return sum / static_cast<double>(cloud.size());
}

}  // namespace loopscan
