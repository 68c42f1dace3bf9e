#pragma once
// The VO's intrinsics of a simulated stereo camera.
#include "loopscan/sim/camera.hpp"
#include "loopscan/vo/vo_config.hpp"

namespace loopscan::test {

inline vo::StereoIntrinsics vo_intrinsics(const sim::StereoCamera& c) {
  vo::StereoIntrinsics k;
  k.fx = c.fx;
  k.fy = c.fy;
  k.cx = c.cx;
  k.cy = c.cy;
  k.baseline_m = c.baseline();
  k.width = c.width;
  k.height = c.height;
  return k;
}

}  // namespace loopscan::test
