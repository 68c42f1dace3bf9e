#pragma once
// Readers for the SO-DSO history files (keyframe poses and their 3D points).
#include <cstddef>
#include <memory>
#include <optional>
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

class LineReader;

// The same records streamed, for a recording too large to hold (what a VO hands over keyframe
// by keyframe): read_sodso_points's checks, skips and clamps, one point or one keyframe's points
// at a time.
class SodsoPointReader {
 public:
  explicit SodsoPointReader(const std::string& path);
  ~SodsoPointReader();
  SodsoPointReader(SodsoPointReader&&) noexcept;
  SodsoPointReader& operator=(SodsoPointReader&&) noexcept;
  // The next point; false at the end of the file.
  bool next(IdPoint& point);
  // Replaces `out` with the points not yet read whose id is at most `last_id` (the points of the
  // keyframe `last_id` and of any skipped keyframe before it).
  void read_until(int last_id, std::vector<IdPoint>& out);
  const PointReadStats& stats() const { return stats_; }

 private:
  std::unique_ptr<LineReader> reader_;
  PointReadStats stats_;
  std::size_t count_ = 0;
  int last_id_ = -1;
  std::optional<IdPoint> ahead_;  // read by read_until, beyond its keyframe
};

}  // namespace loopscan::io
