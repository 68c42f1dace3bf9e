#pragma once
// Ground truth of the loop-closure protocol of the paper's reference Matlab code.
#include <Eigen/Core>
#include <vector>

namespace loopscan::eval {

// threshold_m: a prediction / nearest reference closer than this is a loop.
// mask_width: pairs with |i - j| < mask_width are excluded from ground truth and matching.
// past_only: a streaming run, where query i can only match places j < i (the database grows
// as the drive goes); ground truth then only counts revisits of earlier places.
struct Protocol {
  double threshold_m = 10.0;
  int mask_width = 100;
  bool past_only = false;
};
inline Protocol same_session_protocol() { return {10.0, 100}; }  // KITTI
inline Protocol cross_session_protocol() { return {25.0, 0}; }   // RobotCar

struct GroundTruth {
  std::vector<int> nearest;   // per query: nearest allowed db index, -1 if none
  std::vector<bool> is_loop;  // per query: nearest allowed db entry within the threshold
  int n_loops = 0;            // recall denominator (see reference_quirks)
};

// For each query i: nearest db j with |i - j| >= mask_width (squared Euclidean distance, ties
// -> first j, non-finite distances ignored); a loop if that squared distance < threshold².
// reference_quirks: the Matlab code counted loops with length() of an Nx2 array, which is 2
// when exactly one loop exists; n_loops then reproduces max(N, 2) for N == 1.
GroundTruth compute_ground_truth(const std::vector<Eigen::Vector3d>& query_pos,
                                 const std::vector<Eigen::Vector3d>& db_pos,
                                 const Protocol& protocol, bool reference_quirks = false);

// Loop count as the reference code computed it from the true number of loops.
inline int reference_loop_count(int n_loops, bool reference_quirks) {
  return (reference_quirks && n_loops == 1) ? 2 : n_loops;
}

// True when a and b are closer than the protocol threshold (strict, on squared distances).
inline bool within_threshold(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Protocol& protocol) {
  return (a - b).squaredNorm() < protocol.threshold_m * protocol.threshold_m;
}

}  // namespace loopscan::eval
