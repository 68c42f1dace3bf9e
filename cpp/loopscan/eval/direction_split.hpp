#pragma once
// Place-recognition metrics split by the direction of the revisit: a ground-truth loop is
// "same direction" when the heading of the query and of its nearest allowed reference differ
// by less than 90 degrees, "opposite" otherwise (reverse drives, crossings at wide angles).
#include <vector>

#include "loopscan/eval/precision_recall.hpp"

namespace loopscan::eval {

struct DirectionMetrics {
  PrResult pr;           // this class's loops, plus every query that is no loop at all
  int n_loops = 0;       // ground-truth loops of this class
  int top1_correct = 0;  // ... whose best match is within the threshold
};

struct DirectionSplit {
  DirectionMetrics same, opposite;
};

// `pr` from evaluate_matches on the same positions and protocol; headings: unit forward
// directions of every query / database place (a zero heading counts as same direction).
// Precision of a class counts the false positives of its own loops and of the queries that
// are no loop; recall is over the class's loops. Throws std::invalid_argument on size
// mismatches.
DirectionSplit split_by_direction(const PrResult& pr, const std::vector<Eigen::Vector3d>& query_pos,
                                  const std::vector<Eigen::Vector3d>& db_pos,
                                  const std::vector<Eigen::Vector3d>& query_headings,
                                  const std::vector<Eigen::Vector3d>& db_headings,
                                  const Protocol& protocol);

}  // namespace loopscan::eval
