#pragma once
// A tiny deterministic street scene and its "VO output" (keyframe poses + points with gray
// values) in a few lines: a fast fixture for pipeline tests. The full simulator (world.hpp,
// vo_simulator.hpp) models occlusion, seasons and stereo noise.
#include <cstdint>
#include <vector>

#include "loopscan/core/types.hpp"

namespace loopscan::sim {

struct TinySceneConfig {
  double block_m = 120.0;  // the route drives around a square block ...
  int laps = 2;            // ... this many times, so every place is revisited
  double keyframe_step_m = 1.5;
  int points_per_keyframe = 250;
  double view_depth_m = 40.0;  // points are exported up to this depth in front of the camera
  double depth_noise_m = 0.05;
  std::uint32_t seed = 7;
};

struct TinyScene {
  std::vector<KeyframePose> poses;  // SO-DSO convention: world-to-camera, x right y down z fwd
  std::vector<IdPoint> points;      // world frame, sorted by keyframe id
  std::vector<Eigen::Vector3d> positions;  // ground-truth camera centre of every keyframe id
};

TinyScene make_tiny_scene(const TinySceneConfig& config = {});

}  // namespace loopscan::sim
