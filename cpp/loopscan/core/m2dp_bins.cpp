#include "loopscan/core/m2dp_bins.hpp"

#include <cmath>

#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

using Vec = simd::Lanes<float>::Vec;
typedef int VecI __attribute__((vector_size(simd::kBytes)));
constexpr int kLanes = simd::Lanes<float>::kCount;

inline Vec load(const float* p) {
  Vec v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}

// Lane-wise select; comparisons of GCC vectors give -1 (true) / 0 masks.
inline Vec select(VecI mask, Vec a, Vec b) {
  return (Vec)((mask & (VecI)a) | (~mask & (VecI)b));  // vector casts reinterpret the bits
}

}  // namespace

M2dpBinner::M2dpBinner(int sectors, int rings, double max_radius_m)
    : sectors_(sectors), rings_(rings), max_radius_(max_radius_m) {
  while ((1 << shift_) < sectors) ++shift_;
  for (int j = 1; j < sectors / 4; ++j) {
    const double a = j * 2.0 * M_PI / sectors;
    ray_cos_.push_back(static_cast<float>(std::cos(a)));
    ray_sin_.push_back(static_cast<float>(std::sin(a)));
  }
}

namespace {

// The kernel, unrolled for a fixed number of boundary rays per quadrant.
template <int kRays>
void bin_kernel(const PlanarCloud& c, const float (&axes)[6], float ring_inv, int rings,
                int sector_shift, const float* ray_cos, const float* ray_sin, int* bins) {
  constexpr int per_quadrant = kRays + 1;
  for (std::size_t i = 0; i < c.x.size(); i += kLanes) {
    const Vec px = load(&c.x[i]), py = load(&c.y[i]), pz = load(&c.z[i]);
    const Vec xp = axes[0] * px + axes[1] * py + axes[2] * pz;
    const Vec yp = axes[3] * px + axes[4] * py + axes[5] * pz;
    const Vec r2 = xp * xp + yp * yp;
    Vec rf;
    for (int l = 0; l < kLanes; ++l) rf[l] = __builtin_sqrtf(r2[l]);  // becomes one sqrtps
    rf *= ring_inv;  // may exceed int range: clamped before the conversion
    const VecI ring = __builtin_convertvector(rf < float(rings) ? rf : Vec{} + float(rings), VecI);
    // atan2(y, x) + pi is the angle of (-x, -y): fold it into [0, pi) then [0, pi/2).
    Vec u = -xp, v = -yp;
    const VecI lower = (v < 0) | ((v == 0) & (u < 0));
    u = select(lower, -u, u);
    v = select(lower, -v, v);
    const VecI second = (u <= 0) & (v > 0);
    const Vec u2 = select(second, v, u), v2 = select(second, -u, v);
    VecI sector = ((lower & 2) + (second & 1)) * per_quadrant;
    for (int j = 0; j < kRays; ++j) sector -= (v2 * ray_cos[j] >= u2 * ray_sin[j]);  // -1 masks
    const VecI valid = ring < rings;
    const VecI out = (valid & ((ring << sector_shift) + sector)) | ~valid;  // -1 beyond range
    __builtin_memcpy(bins + i, &out, sizeof out);
  }
}

}  // namespace

void M2dpBinner::bin(const PlanarCloud& c, const Eigen::Vector3d& xa, const Eigen::Vector3d& ya,
                     std::vector<int>& bins) const {
  bins.resize(c.x.size());
  const float axes[6] = {float(xa(0)), float(xa(1)), float(xa(2)),
                         float(ya(0)), float(ya(1)), float(ya(2))};
  const float ring_inv = static_cast<float>(rings_ / max_radius_);
  switch (ray_cos_.size()) {
    case 1: bin_kernel<1>(c, axes, ring_inv, rings_, shift_, ray_cos_.data(), ray_sin_.data(), bins.data()); break;
    case 3: bin_kernel<3>(c, axes, ring_inv, rings_, shift_, ray_cos_.data(), ray_sin_.data(), bins.data()); break;
    case 7: bin_kernel<7>(c, axes, ring_inv, rings_, shift_, ray_cos_.data(), ray_sin_.data(), bins.data()); break;
    default: bin_kernel<0>(c, axes, ring_inv, rings_, shift_, ray_cos_.data(), ray_sin_.data(), bins.data());
  }
}

}  // namespace loopscan
