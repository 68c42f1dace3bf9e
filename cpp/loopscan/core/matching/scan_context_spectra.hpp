#pragma once
// Scan Context places as packed real spectra along the sectors, stored one place after the
// other, and the pair kernel the place database runs on them. Keeping a place contiguous lets
// the database score any subset of places (index candidates) as fast as all of them; the
// packing makes a place exactly as large as its signature (2 R S floats).
#include <cmath>
#include <vector>

#include "loopscan/core/config.hpp"
#include "loopscan/core/payload_arena.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

// The winning alignment of one half: query sector s matches database sector (s + shift) mod S,
// or (shift - s) mod S when mirrored (the convention of scan_context_distance).
struct SectorAlignment {
  double dot = 0;
  int shift = 0;
  bool mirrored = false;
};

class ScanContextSpectra {
 public:
  // Throws std::invalid_argument unless sectors is even and rings, sectors are positive.
  explicit ScanContextSpectra(const ScanContextConfig& config);

  int rings() const { return rings_; }
  int sectors() const { return sectors_; }
  int floats_per_place() const { return 2 * rings_ * sectors_; }

  // Per ring, the DFT along the sectors of the L2-normalised half, packed in S floats:
  //   [Re X_0, Re X_1 .. Re X_{S/2-1} | Re X_{S/2}, Im X_1 .. Im X_{S/2-1}]
  // (Im X_0 = Im X_{S/2} = 0). Structure half first, then intensity. A zero half stays zero.
  // Throws std::invalid_argument if the signature is not 1 x 2RS.
  void pack(const Signature& place, float* out) const;

  // A query packed, plus a copy with the two halves of every ring swapped, which turns the
  // four real products of a complex multiply into two element-wise products.
  struct Query {
    AlignedFloats packed, swapped;
  };
  Query prepare(const Signature& query) const;
  void prepare_packed(const float* packed, Query& out) const;

  // Best dot product of each half (structure, intensity) over every shift and the mirrored
  // order; the SC distance of a half is (1 - dot) / 2.
  void best_dots(const Query& query, const float* place, float best[2]) const;

  // A signature with lateral versions (ScanContextConfig): one prepared query per row; a
  // place's best dots are, per half, the best over the versions.
  std::vector<Query> prepare_versions(const Signature& signature) const;
  void best_dots(const std::vector<Query>& versions, const float* place, float best[2]) const;

  // The alignment behind best_dots for one half (0 structure, 1 intensity), in double;
  // ties go to the smaller shift, unmirrored first.
  SectorAlignment align(const Query& query, const float* place, int half) const;

  // The index key of a packed place, invariant to sector shifts and mirroring: for both halves
  // and every ring, the sector sum (Re X_0, Scan Context's ring key) followed by the magnitudes
  // sqrt(2) |X_f| of the first `frequencies` harmonics (1 <= f < S/2). Over the harmonics it
  // keeps, (|a| - |b|)^2 <= |a - b e^{i phi}|^2 for every shift phi: the key distance is energy
  // two rings cannot share at any shift, which makes it a good proxy for the best dot.
  static int key_dims(int rings, int frequencies) { return 2 * rings * (1 + frequencies); }
  float key(const float* place, std::size_t d, int frequencies) const {
    const int per_ring = 1 + frequencies;
    const std::size_t ring = d / per_ring;  // over both halves: half * R + r
    const int f = static_cast<int>(d % per_ring);
    const float* x = place + ring * sectors_;
    if (f == 0) return x[0];
    const float re = x[f], im = x[sectors_ / 2 + f];
    return 1.41421356f * std::sqrt(re * re + im * im);
  }

 private:
  int rings_, sectors_;
  std::vector<float> forward_;            // S x S: packed spectrum of a unit value in sector s
  std::vector<double> cos_, sin_;         // S x S/2: cos, sin of 2 pi k m / S (row m)
  std::vector<float> inv_cos_, inv_sin_;  // (S/2 + 1) x padded m, weights and 1/S folded in
  int m_padded_;
};

}  // namespace loopscan
