#pragma once
// Precision/recall sequence of the paper's protocol: one prediction per query, ranked by distance.
#include <Eigen/Core>
#include <vector>

#include "loopscan/eval/best_match.hpp"
#include "loopscan/eval/protocol.hpp"

namespace loopscan::eval {

struct PrPoint {
  double precision = 0.0;
  double recall = 0.0;
};

struct RankedMatch {
  QueryMatch m;
  bool is_true = false;  // GT distance(query, match) < threshold
};

struct PrResult {
  std::vector<PrPoint> curve;       // one point per ranked query; empty when n_gt_loops == 0
  std::vector<RankedMatch> ranked;  // in evaluation order
  double auc = 0.0;                 // trapezoid, starting at the first point
  double recall_at_100_precision = 0.0;
  double f1_max = 0.0;
  int n_gt_loops = 0;  // 0 means recall is undefined and all metrics are 0
  int n_queries = 0;
  bool valid() const { return n_gt_loops > 0; }
};

// matches: one per query, any order. They are ranked by distance ascending, ties by query index
// (a stable sort of the query-ordered list, as Matlab's sort), NaN last. Walking ALL of them,
// prediction (a, b) is a true positive if |query_pos[a] - db_pos[b]|² < threshold²; a match
// index outside db_pos is a false positive. Throws std::invalid_argument if a query index is
// outside query_pos. The recall denominator is compute_ground_truth(...).n_loops.
PrResult evaluate_matches(const std::vector<QueryMatch>& matches,
                          const std::vector<Eigen::Vector3d>& query_pos,
                          const std::vector<Eigen::Vector3d>& db_pos, const Protocol& protocol,
                          bool reference_quirks = false);

// The walk down a ranking: fills `curve`, `auc`, `recall_at_100_precision` and `f1_max` of
// `result` from its `ranked` matches and `n_gt_loops` (nothing when that is 0).
void walk_ranking(PrResult& result);

// Metrics over a curve in walk order; shared with the report so plots match the numbers.
// Trapezoid integral of precision over recall from the first point (not from recall 0).
double trapezoid_auc(const std::vector<PrPoint>& curve);
// Recall at the last point whose precision is exactly 1 (0 if none).
double recall_at_full_precision(const std::vector<PrPoint>& curve);
// Points of the curve up to and including the last one at precision exactly 1: the ranked
// matches accepted at 100 % precision (0 if none).
std::size_t full_precision_count(const std::vector<PrPoint>& curve);
// max 2PR/(P+R), a point with P+R == 0 counting as 0.
double f1_max(const std::vector<PrPoint>& curve);

}  // namespace loopscan::eval
