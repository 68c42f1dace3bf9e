#pragma once
// Readers for the SO-DSO history files (keyframe poses and their 3D points).
#include <cstddef>
#include <string>
#include <vector>

#include <loopscan/core/types.hpp>

namespace loopscan::io {

struct PointReadStats {
  std::size_t non_finite_skipped = 0;  // points dropped for a NaN/inf coordinate or intensity
  std::size_t intensity_clamped = 0;   // intensities moved into [0, 255]
};

// `id r00 r01 r02 t0 r10 r11 r12 t1 r20 r21 r22 t2` per line: integer keyframe id and the
// 3x4 world-to-camera matrix, row-major. Ids must be non-negative and strictly increasing, all
// numbers finite; blank lines only at the end. Violations throw InputError. .gz is supported.
std::vector<KeyframePose> read_sodso_poses(const std::string& path);

// `id x y z intensity` per line (world frame). Ids must be non-negative and non-decreasing.
// Points with a non-finite x/y/z/intensity are skipped and intensities outside [0, 255] clamped;
// both are counted in `*stats` (reset first) when given. The intensity is parsed directly as a
// float, matching the rounding of the reference implementation's `>> float`.
std::vector<IdPoint> read_sodso_points(const std::string& path, PointReadStats* stats = nullptr);

}  // namespace loopscan::io
