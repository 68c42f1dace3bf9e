#include "loopscan/eval/protocol.hpp"

#include <cstdlib>
#include <limits>

namespace loopscan::eval {

GroundTruth compute_ground_truth(const std::vector<Eigen::Vector3d>& query_pos,
                                 const std::vector<Eigen::Vector3d>& db_pos,
                                 const Protocol& protocol, bool reference_quirks) {
  const int n_query = static_cast<int>(query_pos.size());
  const int n_db = static_cast<int>(db_pos.size());
  const double threshold_sq = protocol.threshold_m * protocol.threshold_m;

  GroundTruth gt;
  gt.nearest.assign(query_pos.size(), -1);
  gt.is_loop.assign(query_pos.size(), false);
  int n_true = 0;
  for (int i = 0; i < n_query; ++i) {
    double best_sq = std::numeric_limits<double>::infinity();
    int best = -1;
    for (int j = 0; j < n_db; ++j) {
      if (std::abs(i - j) < protocol.mask_width || (protocol.past_only && j > i)) continue;
      const double d_sq = (query_pos[i] - db_pos[j]).squaredNorm();
      // Strict '<' keeps the first j on ties and never picks NaN.
      if (d_sq < best_sq) {
        best_sq = d_sq;
        best = j;
      }
    }
    gt.nearest[i] = best;
    if (best >= 0 && best_sq < threshold_sq) {
      gt.is_loop[i] = true;
      ++n_true;
    }
  }
  gt.n_loops = reference_loop_count(n_true, reference_quirks);
  return gt;
}

}  // namespace loopscan::eval
