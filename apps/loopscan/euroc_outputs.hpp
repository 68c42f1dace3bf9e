#pragma once
// `vo --euroc`: the trajectory in the body frame (TUM format, what evo reads) and, against a TUM
// ground truth, the absolute error after an SE(3) alignment and the relative error (evo's APE
// with --align and RPE with --delta D --delta_unit m).
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "loopscan/io/ground_truth_files.hpp"

namespace loopscan::cli {

// Frames are matched to ground-truth rows by timestamp (nearest, within 5 ms); throws
// io::InputError naming the file when fewer than 2 frames match.
nlohmann::json tum_metrics(const std::vector<double>& times,
                           const std::vector<Eigen::Isometry3d>& T_world_body,
                           const std::vector<io::TumPose>& gt, const std::string& gt_path,
                           double rpe_delta_m);

}  // namespace loopscan::cli
