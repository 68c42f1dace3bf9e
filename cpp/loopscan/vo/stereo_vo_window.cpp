// The keyframe window's bundle adjustment: the last keyframes' poses and the points they share
// refined together, then the observations the optimum does not explain dropped.
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "loopscan/core/timing.hpp"
#include "loopscan/vo/stereo_vo.hpp"

namespace loopscan::vo {

void StereoVo::start_window_ba() {
  ba_.problem.reset();
  if (window_.size() < 2) return;
  auto problem = std::make_unique<BaProblem>();
  const int n = static_cast<int>(window_.size());
  ba_.n_fixed = std::min(config_.fixed_keyframes, n - 1);
  // Points constrained in depth: seen twice in the window or once with a right-image match.
  ba_.weight.clear();
  ba_.local.clear();
  for (const Keyframe& kf : window_)
    for (const Observation& o : kf.observations)
      ba_.weight[o.point] += std::isfinite(o.u_right) ? 2 : 1;
  for (int i = 0; i < n; ++i) {
    problem->T_cam_world.push_back(window_[i].T_world_cam.inverse());
    problem->fixed.push_back(i < ba_.n_fixed);
    for (const Observation& o : window_[i].observations) {
      if (ba_.weight[o.point] < 2) continue;
      auto [it, inserted] =
          ba_.local.try_emplace(o.point, static_cast<int>(problem->points.size()));
      if (inserted) problem->points.push_back(map_[o.point]);
      problem->observations.push_back({i, it->second, o.u, o.v, o.u_right});
    }
  }
  if (problem->observations.empty()) return;
  // Until it is applied nothing it reads changes: track() and estimate_pose() touch neither
  // the window nor the map, only tracks_.
  auto solve = [p = problem.get(), camera = camera_, iterations = config_.ba_iterations,
                huber = config_.ba_huber_px * px_scale_] {
    const auto t0 = StageClock::now();
    bundle_adjust(*p, camera, iterations, huber);
    return ms_since(t0);
  };
  ba_.problem = std::move(problem);
  ba_.done = std::async(config_.ba_on_worker ? std::launch::async : std::launch::deferred, solve);
}

Eigen::Isometry3d StereoVo::apply_window_ba() {
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  if (ba_.problem) {
    const auto t0 = StageClock::now();
    times_.bundle_adjustment += ba_.done.get();
    if (config_.ba_on_worker) times_.ba_wait += ms_since(t0);
    const BaProblem& problem = *ba_.problem;
    const int n = static_cast<int>(window_.size());
    const Eigen::Isometry3d before = window_.back().T_world_cam;
    for (int i = ba_.n_fixed; i < n; ++i) {
      window_[i].T_world_cam = problem.T_cam_world[i].inverse();
      final_keyframe_poses_[window_[i].index] = window_[i].T_world_cam;
    }
    correction = window_.back().T_world_cam * before.inverse();
    for (const auto& [id, index] : ba_.local) map_[id] = problem.points[index];
    // Drop observations the optimum does not explain; a current track among them is dropped
    // too.
    const double max_error = 2.0 * config_.ransac_reprojection_px * px_scale_;
    std::unordered_map<int, bool> bad_current;
    std::size_t k = 0;
    for (int i = 0; i < n; ++i) {
      std::vector<Observation> kept;
      for (const Observation& o : window_[i].observations) {
        if (ba_.weight[o.point] < 2) {
          kept.push_back(o);
          continue;
        }
        const bool bad =
            reprojection_error(problem, problem.observations[k++], camera_) > max_error;
        if (!bad) kept.push_back(o);
        if (bad && i == n - 1) bad_current[o.point] = true;
      }
      window_[i].observations = std::move(kept);
    }
    if (!bad_current.empty()) {
      std::vector<Track> kept;
      for (const Track& t : tracks_)
        if (!bad_current.count(t.point)) kept.push_back(t);
      keyframe_tracks_ -= static_cast<int>(tracks_.size() - kept.size());
      tracks_ = std::move(kept);
    }
    ba_.problem.reset();
  }
  while (static_cast<int>(window_.size()) > config_.window_keyframes) finish_oldest();
  return correction;
}

}  // namespace loopscan::vo
