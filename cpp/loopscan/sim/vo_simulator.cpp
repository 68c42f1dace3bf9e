#include "loopscan/sim/vo_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace loopscan::sim {
namespace {

// The VO's own estimate of every keyframe pose (camera-to-VO-world): the ground-truth relative
// motion perturbed by a random walk, restarted at identity after a reset.
std::vector<Eigen::Isometry3d> drifting_poses(const Trajectory& gt, const std::vector<int>& ids,
                                              const VoSimConfig& c, std::mt19937& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<Eigen::Isometry3d> out;
  std::vector<int> resets = c.reset_keyframe_ids;
  std::sort(resets.begin(), resets.end());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    if (k == 0 || std::binary_search(resets.begin(), resets.end(), ids[k])) {
      out.push_back(Eigen::Isometry3d::Identity());
      continue;
    }
    const Eigen::Isometry3d rel = gt.T_world_cam[ids[k - 1]].inverse() * gt.T_world_cam[ids[k]];
    const double dist = rel.translation().norm();
    const double st = c.drift_translation_per_m * dist;
    const double sr = c.drift_rotation_deg_per_m * M_PI / 180.0 * dist;
    Eigen::Isometry3d noise = Eigen::Isometry3d::Identity();
    noise.linear() = (Eigen::AngleAxisd(sr * n01(rng), Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(0.3 * sr * n01(rng), Eigen::Vector3d::UnitX()) *
                      Eigen::AngleAxisd(0.3 * sr * n01(rng), Eigen::Vector3d::UnitZ()))
                         .toRotationMatrix();
    noise.translation() = Eigen::Vector3d(n01(rng), 0.3 * n01(rng), n01(rng)) * st;
    Eigen::Isometry3d next = out.back() * rel * noise;
    // KITTI's ground truth has 7 digits: its rotations are not quite orthonormal, and chaining
    // thousands of them would leave the VO poses visibly non-rigid.
    next.linear() = Eigen::Quaterniond(next.linear()).normalized().toRotationMatrix();
    out.push_back(next);
  }
  return out;
}

}  // namespace

double noisy_stereo_depth(double depth, double bf, double sigma, double standard_normal) {
  const double disparity = bf / depth + sigma * standard_normal;
  return disparity > 0.0 ? bf / disparity : -1.0;
}

VoOutput simulate_vo(const Trajectory& gt, const std::vector<int>& keyframe_ids, const World& world,
                     const Conditions& conditions, const StereoCamera& cam, const VoSimConfig& c,
                     const std::vector<KeyframePose>& vo_poses) {
  if (!vo_poses.empty() && vo_poses.size() != keyframe_ids.size()) {
    throw std::invalid_argument("simulate_vo: one VO pose per keyframe expected");
  }
  std::mt19937 rng(c.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  const std::vector<Eigen::Isometry3d> drift = drifting_poses(gt, keyframe_ids, c, rng);

  VoOutput out;
  std::size_t rays_total = 0;
  for (std::size_t k = 0; k < keyframe_ids.size(); ++k) {
    const int id = keyframe_ids[k];
    const Eigen::Isometry3d& T_world_cam = gt.T_world_cam.at(id);
    KeyframePose pose;
    pose.id = id;
    Eigen::Isometry3d T_vo_cam;
    if (vo_poses.empty()) {
      T_vo_cam = drift[k];
      pose.T_cam_world = T_vo_cam.inverse().matrix().topRows<3>();
    } else {
      pose = vo_poses[k];
      pose.id = id;
      Eigen::Isometry3d T_cam_vo = Eigen::Isometry3d::Identity();
      T_cam_vo.linear() = pose.T_cam_world.leftCols<3>();
      T_cam_vo.translation() = pose.T_cam_world.col(3);
      T_vo_cam = T_cam_vo.inverse();
    }
    out.poses.push_back(pose);

    // DSO-like selection: random pixels, first surface along the ray, kept with a probability
    // growing with the image gradient there.
    int accepted = 0, rays = 0;
    while (accepted < c.points_per_keyframe && rays < c.max_rays_per_keyframe) {
      ++rays;
      // Pixel centres are integers: the image spans [-0.5, width - 0.5).
      const double px = u01(rng) * cam.width - 0.5, py = u01(rng) * cam.height - 0.5;
      const Eigen::Vector3d ray_cam = cam.ray(px, py);
      const Eigen::Vector3d ray_world = T_world_cam.linear() * ray_cam;
      const auto hit = world.raycast(T_world_cam.translation(), ray_world,
                                     c.max_depth_m / std::max(ray_cam.z(), 1e-6), conditions);
      const double accept_draw = u01(rng), noise_draw = n01(rng), gray_draw = n01(rng);
      if (!hit) continue;
      const double depth = hit->distance * ray_cam.z();  // z in the camera frame
      if (depth < c.min_depth_m || depth > c.max_depth_m) continue;
      const double image_gradient = hit->texture_gradient * depth / cam.fx;
      if (accept_draw >= std::min(1.0, image_gradient / c.gradient_threshold)) continue;
      // Stereo: depth from disparity bf / z, disparity noise -> depth noise ~ z^2.
      const double noisy_depth =
          noisy_stereo_depth(depth, cam.bf, c.disparity_sigma_px, noise_draw);
      if (noisy_depth <= 0.0 || noisy_depth > c.max_depth_m) continue;
      const Eigen::Vector3d p_cam = ray_cam * (noisy_depth / ray_cam.z());
      const double gray =
          std::clamp(World::gray(*hit, conditions) + c.gray_noise * gray_draw, 0.0, 255.0);
      out.points.push_back({id, T_vo_cam * p_cam, static_cast<float>(std::round(gray * 10) / 10)});
      ++accepted;
    }
    rays_total += rays;
    report_progress(c.progress, k + 1, keyframe_ids.size());
  }
  if (!keyframe_ids.empty()) {
    out.mean_points_per_keyframe = double(out.points.size()) / keyframe_ids.size();
    out.mean_rays_per_keyframe = double(rays_total) / keyframe_ids.size();
  }
  return out;
}

}  // namespace loopscan::sim
