#pragma once
// Scan Context spectra in a quarter of the memory: every ring of each half (S packed floats,
// scan_context_spectra.hpp) as S signed bytes with one float scale (max |value| / 127). A
// million places then fit in ~2.6 GB instead of ~9.6 GB, and scoring a place reads 2.5 KB
// instead of 9.6 KB. Scoring expands a record back to floats and runs the same kernel, so
// compact and full databases differ only by the rounding (at most scale / 2 per value).
#include <cstddef>

namespace loopscan {

struct CompactSpectraShape {
  int rows = 0;     // 2 x rings (structure rings, then intensity rings)
  int sectors = 0;  // floats per row of the packed form
  // Record: rows float scales, then rows x sectors bytes (rounded up to whole floats).
  std::size_t floats() const {
    return static_cast<std::size_t>(rows) +
           (static_cast<std::size_t>(rows) * sectors + sizeof(float) - 1) / sizeof(float);
  }
  std::size_t packed_floats() const { return static_cast<std::size_t>(rows) * sectors; }
};

// packed: shape.packed_floats() values; out: shape.floats() floats.
void compress_spectra(const CompactSpectraShape& shape, const float* packed, float* out);
// The inverse (up to rounding): out gets shape.packed_floats() values.
void expand_spectra(const CompactSpectraShape& shape, const float* compact, float* out);

}  // namespace loopscan
