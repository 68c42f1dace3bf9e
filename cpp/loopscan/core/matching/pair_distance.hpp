#pragma once
// Straightforward distances between two place signatures, written like the paper's Matlab.
// They are the oracles of the fast matchers and serve single comparisons.
#include "loopscan/core/config.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

// Which half of an SC / M2DP signature row: structure (count) or intensity.
enum class Component { Structure = 0, Intensity = 1 };

// Scan Context: both halves L2-normalised, d = (1 - dot) / 2 minimised over every sector shift
// of the query and of its mirrored sector order. A zero half counts as orthogonal (d = 0.5).
// `best_shift`/`mirrored` (optional) report the winning alignment: query sector s matches
// database sector (s + shift) mod S, or (shift - s) mod S when mirrored. A query with several
// rows (lateral versions) takes its best row against the database place's first row.
double scan_context_distance(const Signature& query, const Signature& db, Component part,
                             const ScanContextConfig& config = {}, int* best_shift = nullptr,
                             bool* mirrored = nullptr);

// M2DP: (1 - dot) / 2 between the half-rows, minimised over the 4 x 4 version pairs.
double m2dp_distance(const Signature& query, const Signature& db, Component part);

// DELIGHT: mean chi-square 2 (a - b)^2 / (a + b) over bins with a + b > 0, minimised over the
// four region permutations of the PCA sign flips (region r of the query vs r ^ m of the
// database, m in {0, 5, 6, 3}). Two empty signatures: 0.
double delight_distance(const Signature& query, const Signature& db);

// The four region masks, in the order of the authors' permutation table.
constexpr int kDelightRegionMasks[4] = {0, 5, 6, 3};

}  // namespace loopscan
