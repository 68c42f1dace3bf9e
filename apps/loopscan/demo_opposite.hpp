#pragma once
// The demo's look at one opposite-direction revisit: the two drives' scans of the same place,
// side by side in the world, as the paper's forward-only scan and as a two-sided scan.
#include <string>
#include <vector>

#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/direction_split.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan::cli {

// Forward direction (camera z in the world) of each keyframe id.
std::vector<Eigen::Vector3d> headings_of(const sim::Trajectory& route, const std::vector<int>& ids);

// Keyframes (first drive, return) of the reverse revisit closest to the middle of the return,
// at least `gap` places apart, within 5 m, headings > 170 degrees apart (mid-street); {-1, -1} if
// none.
std::pair<int, int> opposite_revisit(const sim::Trajectory& route, const std::vector<int>& ids,
                                     int gap = 100);

// Figures of the pair: each scan in the world frame (ground truth), forward-only and two-sided.
std::vector<report::Figure> opposite_figures(const sim::Trajectory& route, const sim::VoOutput& vo,
                                             std::pair<int, int> pair);

// The per-direction rows of one evaluation: same / opposite top-1 and AUC.
std::vector<std::string> direction_cells(const eval::DirectionSplit& split);

}  // namespace loopscan::cli
