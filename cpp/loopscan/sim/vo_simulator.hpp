#pragma once
// What a stereo VO exports while driving through the synthetic world: keyframe poses (with the
// VO's drift, in its own world frame) and, per keyframe, a few hundred DSO-like points (visible,
// on textured surfaces, stereo depth noise growing with depth squared, gray values).
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/core/progress.hpp"
#include "loopscan/core/types.hpp"
#include "loopscan/sim/camera.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::sim {

struct VoSimConfig {
  int points_per_keyframe = 300;  // DSO's fast setting exports a few hundred points a keyframe
  int max_rays_per_keyframe = 6000;
  double min_depth_m = 1.0;
  double max_depth_m = 45.0;
  double disparity_sigma_px = 0.5;  // stereo matching noise; depth sigma = z^2 / bf * this
  // A pixel is selected with probability min(1, image gradient / threshold); the image gradient
  // is the surface's albedo gradient times the metres one pixel spans (depth / fx).
  double gradient_threshold = 0.04;
  double gray_noise = 1.5;  // sensor noise, gray levels
  // VO drift: each keyframe's relative motion is perturbed by a random walk proportional to the
  // distance travelled (per metre: translation sigma in m, yaw/pitch/roll sigma in degrees).
  double drift_translation_per_m = 0.004;
  double drift_rotation_deg_per_m = 0.01;
  std::vector<int> reset_keyframe_ids;  // the VO restarts here: new VO world frame
  unsigned seed = 1;
  ProgressFn progress;  // (keyframes simulated, all keyframes); results do not depend on it
};

struct VoOutput {
  std::vector<KeyframePose> poses;  // ids = frame ids; SO-DSO: world-to-camera, VO frame
  std::vector<IdPoint> points;      // VO world frame, sorted by keyframe id
  double mean_points_per_keyframe = 0;
  double mean_rays_per_keyframe = 0;
};

// Stereo depth measurement: disparity bf / z plus Gaussian noise (sigma in px, `standard_normal`
// a N(0, 1) draw), back to depth. Returns a negative value when the disparity is not positive.
// To first order the depth sigma is z^2 / bf * sigma.
double noisy_stereo_depth(double depth, double bf, double disparity_sigma_px,
                          double standard_normal);

// Simulates the VO along `gt` at the given keyframes. If `vo_poses_T_cam_world` is non-empty it
// must have one world-to-camera pose per keyframe (e.g. a real SO-DSO run on the same frames):
// points are then expressed through those poses instead of simulated drift.
VoOutput simulate_vo(const Trajectory& gt, const std::vector<int>& keyframe_ids, const World& world,
                     const Conditions& conditions, const StereoCamera& camera,
                     const VoSimConfig& config,
                     const std::vector<KeyframePose>& vo_poses_T_cam_world = {});

}  // namespace loopscan::sim
