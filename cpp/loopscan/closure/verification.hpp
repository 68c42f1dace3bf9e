#pragma once
// Geometric verification of a loop candidate: the map place's cloud is aligned onto the query
// keyframe's by ICP from each yaw guess, and the best alignment must overlap enough, fit
// tightly and be constrained in every direction (no corridor, no near-empty scan).
#include <limits>
#include <string>
#include <vector>

#include "loopscan/closure/birds_eye.hpp"
#include "loopscan/closure/icp.hpp"
#include "loopscan/closure/pose_graph.hpp"
#include "loopscan/core/database/database.hpp"

namespace loopscan::closure {

enum class Verdict {
  Accepted,      // verified and consistent: a loop edge
  Pending,       // verified, waiting for consistent neighbours
  Inconsistent,  // verified, but its neighbours disagree (or the pose graph does)
  FewPoints,     // a cloud too small to align
  LowOverlap,
  HighResidual,
  Degenerate,    // geometry leaves a direction unconstrained
  TooFar,        // the alignment moved the place beyond max_translation_m
  Ambiguous,     // a distinct alignment (over 1 m or 10 degrees away) fits almost as well
};
const char* to_string(Verdict v);

struct Loop {
  int query = 0;  // keyframe id of the query
  PlaceRef match;
  std::size_t place_index = 0;  // the match's index in the database
  // Maps the match's camera frame into the query's: p_query = T_query_match * p_match.
  Eigen::Isometry3d T_query_match = Eigen::Isometry3d::Identity();
  double overlap = 0;
  double rmse_m = 0;
  int iterations = 0;
  double translation_constraint = 0;
  Eigen::Matrix3d translation_information = Eigen::Matrix3d::Zero();  // IcpResult's
  double distance = 0;  // the candidate's descriptor distance
  Verdict verdict = Verdict::LowOverlap;
  bool nearby = false;  // proposed by the trajectory estimate, not by the descriptor
  bool accepted() const { return verdict == Verdict::Accepted; }
};

struct VerifyConfig {
  IcpConfig icp;
  int min_points = 150;  // in each cloud (voxelised)
  // Structure points of the place (off the ground) within the inlier distance of the query's.
  double min_overlap = 0.45;
  // Starts: each yaw guess at the query's position and this far ahead / behind it (a place the
  // descriptor matched a few keyframes off). Every start gets the first ICP stage on the
  // first stage's stride of the points; the best one, and the best that converged elsewhere
  // (over 1 m or 10 degrees away), are refined by the other stages; the better one is judged.
  double along_track_seed_m = 4.0;
  // With the query's bird's-eye grid: ICP starts at each guess and at the bird's-eye search's
  // best poses instead of along the track.
  BirdsEyeConfig birds_eye;
  int screen_iterations = 6;
  double screen_min_overlap = 0.25;  // below this after screening: refused without refining
  double rival_share = 0.8;  // the rival is refined only if it screened this close to the best
  // The refined rival reaching this share of the best's overlap: the place is ambiguous (a
  // street that slides along itself), not verified.
  double ambiguity_share = 0.9;
  // Another place of the same keyframe's candidates aligned at least this share of the
  // accepted one's overlap, putting the query farther than rival_place_m from where the
  // accepted one puts it (both places in one frame): ambiguous (the closer's test; 0 m: off).
  double rival_place_share = 1.0;
  double rival_place_m = 3.0;
  // The place's near structure (within slide_near_m of the query, across the ground) moved
  // +-slide_shift_m and +-1.5 slide_shift_m along the query's track: fitting there at least
  // slide_share as well as where it was aligned, the alignment slid along a street that only
  // far structure held (ambiguous; slide_share 0: off).
  double slide_shift_m = 4.0;
  double slide_near_m = 15.0;
  double slide_share = 1.0;
  double max_rmse_m = 0.45;
  double min_translation_constraint = 0.004;
  double max_translation_m = 8.0;  // farther apart is not the same place
};

void validate(const VerifyConfig& config);

// Where a verified alignment puts the query: its place's world pose composed with the inverse
// of T_query_match. Placements of different frames (VO runs not yet tied, a map not yet joined)
// are not compared.
struct QueryPlacement {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  int frame = -1;  // -1: in no frame yet
  double overlap = 0;
};
QueryPlacement placement(const Loop& loop, const Eigen::Isometry3d& T_world_place, int frame);

// True when another alignment of the same query, in the same frame and at least
// rival_place_share of `accepted`'s overlap, puts the query more than rival_place_m away: the
// places disagree about where the query is, so neither recognises it (a corridor whose
// alignments slide along it). Alignments that screening left coarse (overlap below
// screen_min_overlap) do not count.
bool placed_elsewhere(const QueryPlacement& accepted, const std::vector<QueryPlacement>& others,
                      const VerifyConfig& config);

// The best overlap of the place's near structure moved along the query's track (slide_shift_m,
// 1.5 slide_shift_m, both ways) divided by its overlap at T_query_match; NaN when fewer than
// min_points / 2 structure points are near or none is an inlier at T_query_match.
double slide_ratio(const TargetCloud& query, const PlaceCloud& place,
                   const Eigen::Isometry3d& T_query_match, const VerifyConfig& config = {});

// How far a verified loop's pose may be off, as a model of what its alignment measured
// (calibrated on the loops of simulated and real drives, docs/loop-closing.md): surfaces seen
// from another viewpoint are other sides of the same objects, so the error grows with the
// difference of heading (along the track: the front of a tree or a car against its back) and
// of lateral position; a direction the aligned surfaces leave weak is weak in the edge too.
struct LoopUncertaintyConfig {
  bool measured = true;            // false: every loop gets pose_graph.loop_*_m / _deg
  double base_m = 0.2;             // same place, same heading
  double reverse_along_m = 1.6;    // added along the track for the opposite heading
  double lateral_per_m = 0.3;      // added across the track per metre between the keyframes
  double turn_m = 0.8;             // added across the track at 90 degrees of heading difference
  double geometry_m = 0.1;         // scaled by the weakness of each direction of the surfaces
  double rotation_deg = 1.0;
  // Loops of one revisit err together (the same surfaces seen from the same two tracks): the
  // k-th loop within this much travel gets k times the covariance, so a revisit weighs about
  // as much as a few independent loops, however many keyframes it spans (0: independent).
  double correlation_length_m = 20.0;
};
void validate(const LoopUncertaintyConfig& config);

// The covariance of T_query_match (translation in the query's frame, then rotation).
Covariance6 loop_covariance(const Loop& loop, const LoopUncertaintyConfig& config = {});

// Initial poses to try: the candidate's metric pose first when its method found one (bev), then
// its own yaw (Scan Context, mirrored matches included; bev) and its opposite, or four headings
// when the method gives none (M2DP, DELIGHT).
std::vector<Eigen::Isometry3d> yaw_guesses(const Candidate& candidate);

// Aligns `place` (the map place's cloud, its camera frame) onto `query` and judges it; the
// verdict is Accepted when every geometric test passes (consistency is the closer's).
// `guesses`: initial T_query_match (a yaw from the descriptor, or the pose the graph predicts);
// ICP starts from each, and from the best poses of a bird's-eye search around them when the
// query's grid is given (from each guess shifted along the query's track otherwise).
// `threads` > 1: the starts, then the finalists, aligned on that many threads; the same loop
// whatever the count.
Loop verify_candidate(const TargetCloud& query, const PlaceCloud& place,
                      const std::vector<Eigen::Isometry3d>& guesses, const VerifyConfig& config = {},
                      const BirdsEyeGrid* birds_eye = nullptr, int threads = 1);

}  // namespace loopscan::closure
