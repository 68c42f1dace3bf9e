#pragma once
// The paper's route figure (its Figs. 4 and 6): the route seen from above, the ground-truth
// revisits recognised at 100 % precision in red, the missed ones dark, and a line joining each
// accepted query to the place it matched.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/eval/protocol.hpp"

namespace loopscan::report {

struct RecognitionMap {
  std::string title;                               // the counts are appended
  std::vector<Eigen::Vector3d> query_pos, db_pos;  // as evaluated (index = query / place)
  eval::Protocol protocol;                         // decides which queries are revisits
  // Coordinates drawn; -1: the two of largest spread (top_view_axes), labelled "x [m]" etc.
  int x_axis = -1, y_axis = -1;
};

// Accepted = the ranked matches down to the last one at precision 1 (all true by definition).
std::string recognition_map_svg(const RecognitionMap& map, const eval::PrResult& pr);

// Number of leading ranked matches accepted at 100 % precision.
std::size_t accepted_at_full_precision(const eval::PrResult& pr);

}  // namespace loopscan::report
