// The winning sector alignment of one half, in double precision: the same ring sums and
// inverse DFT as the pair kernel, kept per shift instead of reduced to the best dot (the yaw of
// a match needs the shift, the kernel only the score).
#include <vector>

#include "loopscan/core/matching/scan_context_spectra.hpp"

namespace loopscan {

SectorAlignment ScanContextSpectra::align(const Query& query, const float* place, int half) const {
  const int R = rings_, S = sectors_, H = S / 2;
  const std::size_t off = static_cast<std::size_t>(half) * R * S;
  std::vector<double> a1(S, 0.0), a2(S, 0.0);
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < S; ++j) {
      a1[j] += double(query.packed[off + r * S + j]) * place[off + r * S + j];
      a2[j] += double(query.swapped[off + r * S + j]) * place[off + r * S + j];
    }
  }
  // c_m = (1/S) sum_k w_k (Re P_k cos(2 pi k m / S) - Im P_k sin(2 pi k m / S)).
  // Correlation c_m pairs query sector t + m with place sector t: shift = -m. Convolution c_m
  // pairs query sector s with place sector m - s: mirrored, shift = m.
  std::vector<double> re(H, 0.0), im(H, 0.0);
  SectorAlignment best{-3.0, 0, false};
  for (int mirrored = 0; mirrored < 2; ++mirrored) {
    for (int k = 1; k < H; ++k) {
      const double x = a1[k], y = a1[H + k], z = a2[k], u = a2[H + k];
      re[k] = 2.0 * (mirrored ? x - y : x + y);
      im[k] = 2.0 * (mirrored ? z + u : z - u);
    }
    for (int shift = 0; shift < S; ++shift) {
      const int m = mirrored ? shift : (S - shift) % S;
      const double* cs = &cos_[static_cast<std::size_t>(m) * H];
      const double* sn = &sin_[static_cast<std::size_t>(m) * H];
      double c = a1[0] + ((m % 2) ? -a1[H] : a1[H]);
      for (int k = 1; k < H; ++k) c += re[k] * cs[k] - im[k] * sn[k];
      c /= S;
      if (c > best.dot) best = {c, shift, mirrored != 0};
    }
  }
  return best;
}

}  // namespace loopscan
