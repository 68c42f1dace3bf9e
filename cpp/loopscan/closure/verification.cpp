#include "loopscan/closure/verification.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "loopscan/core/parallel.hpp"

namespace loopscan::closure {

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::Accepted: return "accepted";
    case Verdict::Pending: return "pending";
    case Verdict::Inconsistent: return "inconsistent";
    case Verdict::FewPoints: return "few-points";
    case Verdict::LowOverlap: return "low-overlap";
    case Verdict::HighResidual: return "high-residual";
    case Verdict::Degenerate: return "degenerate";
    case Verdict::TooFar: return "too-far";
    case Verdict::Ambiguous: return "ambiguous";
  }
  return "?";
}

void validate(const VerifyConfig& c) {
  validate(c.icp);
  validate(c.birds_eye);
  if (c.min_points < 3 || c.min_points > (1 << 22) || !(c.min_overlap >= 0 && c.min_overlap <= 1) ||
      !(c.max_rmse_m > 0 && c.max_rmse_m <= 100) ||
      !(c.min_translation_constraint >= 0 && c.min_translation_constraint <= 1) ||
      !(c.max_translation_m > 0 && c.max_translation_m <= 1000) ||
      !(c.along_track_seed_m >= 0 && c.along_track_seed_m <= 100) || c.screen_iterations < 1 ||
      !(c.rival_share >= 0 && c.rival_share <= 1) ||
      !(c.ambiguity_share >= 0 && c.ambiguity_share <= 1) ||
      !(c.rival_place_m >= 0 && c.rival_place_m <= 1000) ||
      !(c.rival_place_share >= 0 && c.rival_place_share <= 10) || c.screen_iterations > 1000 ||
      !(c.slide_shift_m > 0 && c.slide_shift_m <= 100) ||
      !(c.slide_near_m > 0 && c.slide_near_m <= 1000) ||
      !(c.slide_share >= 0 && c.slide_share <= 10) ||
      !(c.screen_min_overlap >= 0 && c.screen_min_overlap <= 1)) {
    throw std::invalid_argument(
        "verify config: min_points in [3, 2^22], min_overlap in [0, 1], max_rmse_m in (0, 100], "
        "min_translation_constraint in [0, 1], max_translation_m in (0, 1000], "
        "along_track_seed_m in [0, 100], screen_iterations in [1, 1000], screen_min_overlap in "
        "[0, 1], rival_share and ambiguity_share in [0, 1], rival_place_share in [0, 10], "
        "rival_place_m in [0, 1000], slide_shift_m in (0, 100], slide_near_m in (0, 1000], "
        "slide_share in [0, 10]");
  }
}

void validate(const LoopUncertaintyConfig& c) {
  for (double v : {c.base_m, c.rotation_deg}) {
    if (!(v > 0 && v <= 1e3)) throw std::invalid_argument("loop uncertainty: base_m and rotation_deg in (0, 1000]");
  }
  for (double v : {c.reverse_along_m, c.lateral_per_m, c.turn_m, c.geometry_m, c.correlation_length_m}) {
    if (!(v >= 0 && v <= 1e3)) throw std::invalid_argument("loop uncertainty: growth terms in [0, 1000]");
  }
}

Covariance6 loop_covariance(const Loop& loop, const LoopUncertaintyConfig& c) {
  const double yaw = yaw_of(loop.T_query_match);
  const double along = c.base_m + c.reverse_along_m * 0.5 * (1.0 - std::cos(yaw));
  const double across = c.base_m + c.lateral_per_m * std::abs(loop.T_query_match.translation().x()) +
                        c.turn_m * std::abs(std::sin(yaw));
  Eigen::Matrix3d view = Eigen::Vector3d(across * across, c.base_m * c.base_m, along * along).asDiagonal();
  // Directions the surfaces constrain weakly (eigenvalue lambda of the per-inlier normal
  // matrix, 1/3 when all are alike) add geometry_m^2 / (3 lambda).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(loop.translation_information);
  Eigen::Matrix3d geometry = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) {
    const double lambda = std::max(eig.eigenvalues()[k], 1e-4);
    geometry += c.geometry_m * c.geometry_m / (3.0 * lambda) * eig.eigenvectors().col(k) *
                eig.eigenvectors().col(k).transpose();
  }
  Covariance6 out = Covariance6::Zero();
  out.topLeftCorner<3, 3>() = view + geometry;
  const double r = c.rotation_deg * M_PI / 180.0;
  out.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * (r * r);
  return out;
}

QueryPlacement placement(const Loop& loop, const Eigen::Isometry3d& T_world_place, int frame) {
  return {(T_world_place * loop.T_query_match.inverse()).translation(), frame, loop.overlap};
}

bool placed_elsewhere(const QueryPlacement& accepted, const std::vector<QueryPlacement>& others,
                      const VerifyConfig& config) {
  if (!(config.rival_place_m > 0) || accepted.frame < 0) return false;
  for (const QueryPlacement& o : others) {
    if (o.frame == accepted.frame && o.overlap >= config.screen_min_overlap &&
        o.overlap >= config.rival_place_share * accepted.overlap &&
        (o.position - accepted.position).norm() > config.rival_place_m)
      return true;
  }
  return false;
}

double slide_ratio(const TargetCloud& query, const PlaceCloud& place,
                   const Eigen::Isometry3d& T_query_match, const VerifyConfig& config) {
  const Eigen::Matrix3f R = T_query_match.linear().cast<float>();
  const Eigen::Vector3f t = T_query_match.translation().cast<float>();
  Points3f near;
  for (std::size_t i = 0; i < place.structure && i < place.points.size(); ++i) {
    if (within_ground_range(R * place.points[i] + t, config.slide_near_m))
      near.push_back(place.points[i]);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (int(near.size()) < config.min_points / 2) return nan;
  const double at = score_alignment(near, query, T_query_match, config.icp).overlap;
  if (!(at > 0)) return nan;
  double moved = 0;
  const double s = config.slide_shift_m;
  for (double along : {-1.5 * s, -s, s, 1.5 * s}) {
    Eigen::Isometry3d T = T_query_match;
    T.translation().z() += along;
    moved = std::max(moved, score_alignment(near, query, T, config.icp).overlap);
  }
  return moved / at;
}

std::vector<Eigen::Isometry3d> yaw_guesses(const Candidate& c) {
  // (A mirrored match's yaw already accounts for the reflection: starting also from the
  // reflected yaw cost 20 % more time and no loop on the simulated drives.)
  const std::vector<double> yaws = std::isfinite(c.yaw_rad)
                                       ? std::vector<double>{c.yaw_rad, c.yaw_rad + M_PI}
                                       : std::vector<double>{0.0, M_PI / 2, M_PI, -M_PI / 2};
  std::vector<Eigen::Isometry3d> out;
  if (std::isfinite(c.yaw_rad) && std::isfinite(c.x_m) && std::isfinite(c.z_m)) {
    Eigen::Isometry3d pose = yaw_rotation(c.yaw_rad);
    pose.translation() = Eigen::Vector3d(c.x_m, 0.0, c.z_m);
    out.push_back(pose);
  }
  for (double yaw : yaws) out.push_back(yaw_rotation(yaw));
  return out;
}

Loop verify_candidate(const TargetCloud& query, const PlaceCloud& place,
                      const std::vector<Eigen::Isometry3d>& guesses, const VerifyConfig& config,
                      const BirdsEyeGrid* birds_eye, int threads) {
  validate(config);
  Loop loop;
  if (int(query.size()) < config.min_points || int(place.points.size()) < config.min_points ||
      int(place.structure) < config.min_points / 2) {
    loop.verdict = Verdict::FewPoints;
    return loop;
  }
  std::vector<Eigen::Isometry3d> starts = guesses;
  if (birds_eye != nullptr) {
    for (const BirdsEyePose& p : birds_eye_search(*birds_eye, place, guesses)) {
      starts.push_back(p.T_query_place);
    }
  } else {
    const double a = config.along_track_seed_m;
    for (double along : {a, -a, 2 * a, -2 * a, 3 * a, -3 * a}) {
      for (const Eigen::Isometry3d& guess : guesses) {
        Eigen::Isometry3d T = guess;
        T.translation() += Eigen::Vector3d(0, 0, along);
        starts.push_back(T);
      }
    }
  }
  // Screen every start with the coarse stage on a quarter of the points, refine the best.
  IcpConfig screen = config.icp, refine = config.icp;
  screen.stage_distances_m.resize(1);
  screen.stage_strides.assign(1, 1);
  screen.max_iterations_per_stage = config.screen_iterations;
  refine.stage_distances_m.erase(refine.stage_distances_m.begin());
  refine.stage_strides.erase(refine.stage_strides.begin());
  const std::size_t stride = std::size_t(config.icp.stage_strides.front());
  const Points3f subset = every_nth(place.points, stride);
  const std::size_t subset_structure = (place.structure + stride - 1) / stride;
  std::vector<IcpResult> screened(starts.size());
  for_each_index(starts.size(), threads, [&](std::size_t i) {
    screened[i] = align_point_to_plane(subset, query, starts[i], screen, subset_structure);
  });
  for (const IcpResult& r : screened) loop.iterations += r.iterations;
  // The best start, and the best one that converged elsewhere (a street looks much like its
  // mirror image after a coarse stage): both are refined, the better refined one wins.
  const auto far_from = [](const IcpResult& x, const IcpResult& y) {
    const Eigen::Isometry3d d = x.T_target_source.inverse() * y.T_target_source;
    return d.translation().norm() > 1.0 || Eigen::AngleAxisd(d.rotation()).angle() > 10 * M_PI / 180;
  };
  std::size_t b = 0;
  for (std::size_t i = 1; i < screened.size(); ++i) {
    if (screened[i].overlap > screened[b].overlap) b = i;
  }
  std::vector<std::size_t> finalists = {b};
  std::size_t rival = b;
  for (std::size_t i = 0; i < screened.size(); ++i) {
    if (far_from(screened[b], screened[i]) && (rival == b || screened[i].overlap > screened[rival].overlap)) rival = i;
  }
  if (rival != b && screened[rival].overlap >= config.rival_share * screened[b].overlap) {
    finalists.push_back(rival);
  }
  IcpResult best = screened[b];
  if (best.overlap < config.screen_min_overlap) {  // clearly no match: skip the refinement
    loop.T_query_match = best.T_target_source;
    loop.overlap = best.overlap;
    loop.verdict = Verdict::LowOverlap;
    return loop;
  }
  std::vector<IcpResult> refined(finalists.size());
  for_each_index(finalists.size(), threads, [&](std::size_t k) {
    const Eigen::Isometry3d start = screened[finalists[k]].T_target_source;
    refined[k] = refine.stage_distances_m.empty()
                     ? score_alignment(place.points, query, start, config.icp, place.structure)
                     : align_point_to_plane(place.points, query, start, refine, place.structure);
  });
  for (std::size_t k = 0; k < refined.size(); ++k) {
    loop.iterations += refined[k].iterations;
    if (k == 0 || refined[k].overlap > best.overlap) best = refined[k];
  }
  bool ambiguous = false;
  for (const IcpResult& r : refined) {
    ambiguous |= far_from(best, r) && r.overlap >= config.ambiguity_share * best.overlap;
  }
  loop.T_query_match = best.T_target_source;
  loop.overlap = best.overlap;
  loop.rmse_m = best.rmse_m;
  loop.translation_constraint = best.translation_constraint;
  loop.translation_information = best.translation_information;
  if (best.overlap < config.min_overlap) {
    loop.verdict = Verdict::LowOverlap;
  } else if (best.rmse_m > config.max_rmse_m) {
    loop.verdict = Verdict::HighResidual;
  } else if (best.translation_constraint < config.min_translation_constraint) {
    loop.verdict = Verdict::Degenerate;
  } else if (best.T_target_source.translation().norm() > config.max_translation_m) {
    loop.verdict = Verdict::TooFar;
  } else if (ambiguous ||
             (config.slide_share > 0 &&  // NaN (too little near): no verdict
              slide_ratio(query, place, best.T_target_source, config) >= config.slide_share)) {
    loop.verdict = Verdict::Ambiguous;
  } else {
    loop.verdict = Verdict::Accepted;
  }
  return loop;
}

}  // namespace loopscan::closure
