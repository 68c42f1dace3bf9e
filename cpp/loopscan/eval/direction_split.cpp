#include "loopscan/eval/direction_split.hpp"

#include <stdexcept>

namespace loopscan::eval {
namespace {

// The walk of evaluate_matches over a subset of its ranking, with its own recall denominator.
void finish(DirectionMetrics& d) {
  PrResult& r = d.pr;
  r.n_gt_loops = d.n_loops;
  r.n_queries = static_cast<int>(r.ranked.size());
  if (d.n_loops == 0) return;
  int tp = 0;
  for (std::size_t k = 0; k < r.ranked.size(); ++k) {
    if (r.ranked[k].is_true) ++tp;
    r.curve.push_back({static_cast<double>(tp) / static_cast<double>(k + 1),
                       static_cast<double>(tp) / static_cast<double>(d.n_loops)});
  }
  r.auc = trapezoid_auc(r.curve);
  r.recall_at_100_precision = recall_at_full_precision(r.curve);
  r.f1_max = f1_max(r.curve);
}

}  // namespace

DirectionSplit split_by_direction(const PrResult& pr, const std::vector<Eigen::Vector3d>& query_pos,
                                  const std::vector<Eigen::Vector3d>& db_pos,
                                  const std::vector<Eigen::Vector3d>& query_headings,
                                  const std::vector<Eigen::Vector3d>& db_headings,
                                  const Protocol& protocol) {
  if (query_headings.size() != query_pos.size() || db_headings.size() != db_pos.size()) {
    throw std::invalid_argument("split_by_direction: one heading per position expected");
  }
  const GroundTruth gt = compute_ground_truth(query_pos, db_pos, protocol);
  // 0: no loop, 1: same direction, 2: opposite.
  std::vector<int> cls(query_pos.size(), 0);
  DirectionSplit out;
  for (std::size_t i = 0; i < query_pos.size(); ++i) {
    if (!gt.is_loop[i]) continue;
    const bool opposite =
        query_headings[i].dot(db_headings[static_cast<std::size_t>(gt.nearest[i])]) < 0;
    cls[i] = opposite ? 2 : 1;
    ++(opposite ? out.opposite : out.same).n_loops;
  }
  for (const RankedMatch& r : pr.ranked) {
    const int c = cls.at(static_cast<std::size_t>(r.m.query));
    for (int k = 1; k <= 2; ++k) {
      DirectionMetrics& d = k == 1 ? out.same : out.opposite;
      if (c != 0 && c != k) continue;
      d.pr.ranked.push_back(r);
      if (c == k && r.is_true) ++d.top1_correct;
    }
  }
  finish(out.same);
  finish(out.opposite);
  return out;
}

}  // namespace loopscan::eval
