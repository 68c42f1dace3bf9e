// The keyframe window's bundle adjustment: the last keyframes' poses and the points they share
// refined together, then the observations the optimum does not explain dropped.
#include <cmath>
#include <unordered_map>

#include "loopscan/vo/stereo_vo.hpp"

namespace loopscan::vo {

void StereoVo::run_window_ba(Eigen::Isometry3d& T) {
  if (window_.size() < 2) return;
  BaProblem problem;
  const int n = static_cast<int>(window_.size());
  const int n_fixed = std::min(config_.fixed_keyframes, n - 1);
  // Points constrained in depth: seen twice in the window or once with a right-image match.
  std::unordered_map<int, int> weight;
  for (const Keyframe& kf : window_)
    for (const Observation& o : kf.observations)
      weight[o.point] += std::isfinite(o.u_right) ? 2 : 1;
  std::unordered_map<int, int> local;
  for (int i = 0; i < n; ++i) {
    problem.T_cam_world.push_back(window_[i].T_world_cam.inverse());
    problem.fixed.push_back(i < n_fixed);
    for (const Observation& o : window_[i].observations) {
      if (weight[o.point] < 2) continue;
      auto [it, inserted] = local.try_emplace(o.point, static_cast<int>(problem.points.size()));
      if (inserted) problem.points.push_back(map_[o.point]);
      problem.observations.push_back({i, it->second, o.u, o.v, o.u_right});
    }
  }
  if (problem.observations.empty()) return;
  bundle_adjust(problem, camera_, config_.ba_iterations, config_.ba_huber_px * px_scale_);
  for (int i = n_fixed; i < n; ++i) {
    window_[i].T_world_cam = problem.T_cam_world[i].inverse();
    final_keyframe_poses_[window_[i].index] = window_[i].T_world_cam;
  }
  for (const auto& [id, index] : local) map_[id] = problem.points[index];
  // Drop observations the optimum does not explain; a current track among them is dropped too.
  const double max_error = 2.0 * config_.ransac_reprojection_px * px_scale_;
  std::unordered_map<int, bool> bad_current;
  std::size_t k = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<Observation> kept;
    for (const Observation& o : window_[i].observations) {
      if (weight[o.point] < 2) {
        kept.push_back(o);
        continue;
      }
      const bool bad = reprojection_error(problem, problem.observations[k++], camera_) > max_error;
      if (!bad) kept.push_back(o);
      if (bad && i == n - 1) bad_current[o.point] = true;
    }
    window_[i].observations = std::move(kept);
  }
  if (!bad_current.empty()) {
    std::vector<Track> kept;
    for (const Track& t : tracks_)
      if (!bad_current.count(t.point)) kept.push_back(t);
    tracks_ = std::move(kept);
  }
  T = window_.back().T_world_cam;
}

}  // namespace loopscan::vo
