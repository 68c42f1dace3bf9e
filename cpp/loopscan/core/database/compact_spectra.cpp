#include "loopscan/core/database/compact_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace loopscan {

void compress_spectra(const CompactSpectraShape& shape, const float* packed, float* out) {
  const int S = shape.sectors;
  std::memset(out, 0, shape.floats() * sizeof(float));
  auto* bytes = reinterpret_cast<std::int8_t*>(out + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const float* x = packed + static_cast<std::size_t>(r) * S;
    float peak = 0;
    for (int k = 0; k < S; ++k) peak = std::max(peak, std::abs(x[k]));
    const float scale = peak / 127.f;
    out[r] = scale;
    if (scale == 0) continue;  // an empty ring (or half) stays exactly zero
    const float inverse = 1.f / scale;
    std::int8_t* q = bytes + static_cast<std::size_t>(r) * S;
    for (int k = 0; k < S; ++k) {
      q[k] = static_cast<std::int8_t>(std::clamp(std::lrint(x[k] * inverse), -127L, 127L));
    }
  }
}

void expand_spectra(const CompactSpectraShape& shape, const float* compact, float* out) {
  const int S = shape.sectors;
  const auto* bytes = reinterpret_cast<const std::int8_t*>(compact + shape.rows);
  for (int r = 0; r < shape.rows; ++r) {
    const float scale = compact[r];
    const std::int8_t* q = bytes + static_cast<std::size_t>(r) * S;
    float* x = out + static_cast<std::size_t>(r) * S;
    for (int k = 0; k < S; ++k) x[k] = scale * static_cast<float>(q[k]);
  }
}

}  // namespace loopscan
