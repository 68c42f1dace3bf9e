#include "loopscan/eval/precision_recall.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loopscan::eval {

namespace {

// Ascending distance with NaN last; equal keys fall back to the query index so the result does
// not depend on the input order (Matlab sorted the query-ordered vector stably).
bool ranks_before(const QueryMatch& a, const QueryMatch& b) {
  const bool a_nan = std::isnan(a.distance);
  const bool b_nan = std::isnan(b.distance);
  if (a_nan != b_nan) return b_nan;
  if (!a_nan && a.distance != b.distance) return a.distance < b.distance;
  return a.query < b.query;
}

}  // namespace

double trapezoid_auc(const std::vector<PrPoint>& curve) {
  double area = 0.0;
  for (std::size_t k = 1; k < curve.size(); ++k) {
    area += (curve[k].recall - curve[k - 1].recall) *
            (curve[k].precision + curve[k - 1].precision) / 2.0;
  }
  return area;
}

std::size_t full_precision_count(const std::vector<PrPoint>& curve) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < curve.size(); ++k) {
    if (curve[k].precision == 1.0) n = k + 1;
  }
  return n;
}

double recall_at_full_precision(const std::vector<PrPoint>& curve) {
  const std::size_t n = full_precision_count(curve);
  return n > 0 ? curve[n - 1].recall : 0.0;
}

double f1_max(const std::vector<PrPoint>& curve) {
  double best = 0.0;
  for (const PrPoint& p : curve) {
    const double sum = p.precision + p.recall;
    if (sum > 0.0) best = std::max(best, 2.0 * p.precision * p.recall / sum);
  }
  return best;
}

void walk_ranking(PrResult& result) {
  result.curve.clear();
  // Without ground-truth loops recall is undefined: keep the ranking, report no curve.
  if (result.n_gt_loops == 0) return;
  result.curve.reserve(result.ranked.size());
  int tp = 0;
  for (std::size_t k = 0; k < result.ranked.size(); ++k) {
    if (result.ranked[k].is_true) ++tp;
    const double precision = static_cast<double>(tp) / static_cast<double>(k + 1);
    const double recall = static_cast<double>(tp) / static_cast<double>(result.n_gt_loops);
    result.curve.push_back({precision, recall});
  }
  result.auc = trapezoid_auc(result.curve);
  result.recall_at_100_precision = recall_at_full_precision(result.curve);
  result.f1_max = f1_max(result.curve);
}

PrResult evaluate_matches(const std::vector<QueryMatch>& matches,
                          const std::vector<Eigen::Vector3d>& query_pos,
                          const std::vector<Eigen::Vector3d>& db_pos, const Protocol& protocol,
                          bool reference_quirks) {
  for (const QueryMatch& m : matches) {
    if (m.query < 0 || m.query >= static_cast<int>(query_pos.size())) {
      throw std::invalid_argument("evaluate_matches: query index " + std::to_string(m.query) +
                                  " outside query_pos (size " + std::to_string(query_pos.size()) +
                                  ")");
    }
  }
  PrResult result;
  result.n_queries = static_cast<int>(matches.size());
  result.n_gt_loops = compute_ground_truth(query_pos, db_pos, protocol, reference_quirks).n_loops;

  std::vector<QueryMatch> order = matches;
  std::stable_sort(order.begin(), order.end(), ranks_before);

  result.ranked.reserve(order.size());
  for (const QueryMatch& m : order) {
    const bool match_valid = m.match >= 0 && m.match < static_cast<int>(db_pos.size());
    const bool is_true =
        match_valid && within_threshold(query_pos[m.query], db_pos[m.match], protocol);
    result.ranked.push_back({m, is_true});
  }
  walk_ranking(result);
  return result;
}

}  // namespace loopscan::eval
