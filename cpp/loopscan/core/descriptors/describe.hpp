#pragma once
// One entry point for the descriptors.
#include "loopscan/core/config.hpp"
#include "loopscan/core/descriptors/birds_eye_place.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

// Default mode's Scan Context lateral versions: half a lane and a lane to either side (m).
inline const std::vector<double> kDefaultLateralVersions = {-3.5, -1.75, 1.75, 3.5};

struct DescriptorConfig {
  ScanContextConfig scan_context;
  M2dpConfig m2dp;
  DelightConfig delight;
  BirdsEyePlaceConfig birds_eye;  // always in the keyframe's camera frame
  // Sets the mode of every descriptor and the radius of SC / M2DP to the imitation range; in
  // default mode Scan Context uses the camera frame and kDefaultLateralVersions.
  static DescriptorConfig for_mode(Mode mode, double range_m = 45.0);
};

// The frame `method`'s descriptor is computed in under `config` (reference mode: always the
// paper's PCA frame).
DescriptorFrame descriptor_frame(Method method, const DescriptorConfig& config);

// Signature of one imitated (filtered, camera-frame) scan. `frame` (optional) receives the
// descriptor's axes in the camera frame for Scan Context (PCA basis, rows = axes), the
// identity for the others; the database turns sector shifts into yaw with it. Throws
// std::invalid_argument on an invalid config or a scan with a NaN or infinite coordinate (a
// NaN gray value gives a NaN signature, which the database refuses).
Signature describe(Method method, const Cloud& scan, const DescriptorConfig& config,
                   Eigen::Matrix3d* frame = nullptr);

}  // namespace loopscan
