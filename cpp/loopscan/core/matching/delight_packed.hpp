#pragma once
// DELIGHT histograms packed in single precision, one place contiguous ([region][bin], bins
// padded to a multiple of 8), and the pair distance on them: the fast path of the offline
// matcher and of the place database, tested against delight_distance.
#include "loopscan/core/signature.hpp"

namespace loopscan {

struct DelightTotals {
  double sum = 0;      // all counts of the place
  double nonzero = 0;  // bins with a count
};

constexpr int kDelightRegions = 16;

// Padded bin count for a signature of `columns` bins.
int delight_padded_bins(int columns);

// Writes the 16 x columns signature into out (16 x padded bins, zero padding).
DelightTotals delight_pack(const Signature& place, int padded_bins, float* out);

// delight_distance of two packed places.
double delight_packed_distance(const float* a, const DelightTotals& ta, const float* b,
                               const DelightTotals& tb, int padded_bins);

}  // namespace loopscan
