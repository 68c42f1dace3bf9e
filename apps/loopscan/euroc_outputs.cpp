#include "euroc_outputs.hpp"

#include <algorithm>
#include <cmath>

#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan::cli {

nlohmann::json tum_metrics(const std::vector<double>& times,
                           const std::vector<Eigen::Isometry3d>& T_world_body,
                           const std::vector<io::TumPose>& gt, const std::string& gt_path,
                           double rpe_delta_m) {
  std::vector<Eigen::Isometry3d> gt_poses, estimate;
  std::vector<Eigen::Vector3d> gt_positions, positions;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const auto after = std::lower_bound(gt.begin(), gt.end(), times[i],
                                        [](const io::TumPose& p, double t) { return p.time < t; });
    const io::TumPose* best = nullptr;
    for (auto it : {after, after == gt.begin() ? gt.end() : after - 1}) {
      if (it != gt.end() &&
          (!best || std::abs(it->time - times[i]) < std::abs(best->time - times[i])))
        best = &*it;
    }
    if (!best || std::abs(best->time - times[i]) > 0.005) continue;
    gt_poses.push_back(best->T_world_body);
    estimate.push_back(T_world_body[i]);
    gt_positions.push_back(best->T_world_body.translation());
    positions.push_back(T_world_body[i].translation());
  }
  if (gt_poses.size() < 2)
    throw io::InputError(gt_path, 0,
                         "ground-truth rows within 5 ms of at least 2 frames (matched " +
                             std::to_string(gt_poses.size()) + " of " +
                             std::to_string(times.size()) + ")");
  double path = 0;
  for (std::size_t i = 1; i < gt_positions.size(); ++i)
    path += (gt_positions[i] - gt_positions[i - 1]).norm();
  const double ate = eval::aligned_rmse(gt_positions, positions);
  const eval::RelativeError rpe = eval::relative_pose_error(gt_poses, estimate, rpe_delta_m);
  return {{"ground_truth", gt_path},
          {"matched_frames", gt_poses.size()},
          {"path_length_m", path},
          {"ate_rmse_m", ate},
          {"ate_percent_of_path", path > 0 ? 100.0 * ate / path : 0.0},
          {"rpe_delta_m", rpe_delta_m},
          {"rpe_pairs", rpe.pairs},
          {"rpe_translation_rmse_m", rpe.translation_rmse_m},
          {"rpe_rotation_rmse_deg", rpe.rotation_rmse_deg}};
}

}  // namespace loopscan::cli
