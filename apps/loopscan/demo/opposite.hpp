#pragma once
// The demo's look at one opposite-direction revisit: the two drives' scans of the same place,
// side by side in the world, as the paper's forward-only scan and as a two-sided scan.
#include <map>
#include <string>
#include <vector>

#include "loopscan/config/configuration.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan::cli {

// The scans (camera frame, Cartesian-filtered) the imitation gives these keyframes, in one pass
// over the drive; a keyframe without a scan is missing from the map.
std::map<int, Cloud> scans_at(const sim::VoOutput& vo, const ImitationConfig& imitation,
                              const std::vector<int>& keyframe_ids);

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

// The reverse revisit as the bird's-eye place (one descriptor a place, `--method bev`)
// recognises it: the first drive evaluated against itself as `evaluate` does, then, of the
// opposite-direction revisits it ranks right at top-1, the one nearest the middle of the return:
// both scans in the query's camera frame, the place's scan moved by the pose its image search
// found and by the true pose. Empty when no opposite-direction revisit is right at top-1.
std::vector<report::Figure> birds_eye_revisit_figures(const sim::Trajectory& route,
                                                      const sim::VoOutput& vo,
                                                      const Configuration& c, int threads);

}  // namespace loopscan::cli
