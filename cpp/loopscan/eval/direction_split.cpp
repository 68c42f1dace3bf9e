#include "loopscan/eval/direction_split.hpp"

#include <stdexcept>

namespace loopscan::eval {
namespace {

// The walk of evaluate_matches over a subset of its ranking, with its own recall denominator.
void finish(DirectionMetrics& d) {
  d.pr.n_gt_loops = d.n_loops;
  d.pr.n_queries = static_cast<int>(d.pr.ranked.size());
  walk_ranking(d.pr);
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
