// ICP and verification against known transforms on simulated street scenes, the oracles of
// the voxel grid and the nearest-neighbour index, and the failure modes verification refuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <tuple>

#include <Eigen/Eigenvalues>

#include "loopscan/closure/icp.hpp"
#include "loopscan/closure/verification.hpp"
#include "scene_points.hpp"

namespace loopscan {
namespace {

using closure::Points3f;

Eigen::Isometry3d pose(double yaw_deg, double pitch_deg, double roll_deg, Eigen::Vector3d t) {
  Eigen::Isometry3d T = closure::yaw_rotation(yaw_deg * M_PI / 180);
  T.linear() = T.linear() *
               Eigen::AngleAxisd(pitch_deg * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix() *
               Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * 180 / M_PI;
}

// Two independent samples of one scene: the target as is, the source seen from T^-1 (so that
// T_target_source = T), both with 3 cm noise and voxelised.
std::pair<Points3f, closure::PlaceCloud> two_views_of(const Points3f& all, unsigned seed,
                                                      const Eigen::Isometry3d& T) {
  Points3f a, b;
  for (std::size_t i = 0; i < all.size(); ++i) (i % 2 ? b : a).push_back(all[i]);
  return {closure::voxel_cloud(test::transformed(a, Eigen::Isometry3d::Identity(), 0.03, seed + 1)),
          closure::to_place_cloud(closure::TargetCloud(
              closure::voxel_cloud(test::transformed(b, T.inverse(), 0.03, seed + 2))))};
}

std::pair<Points3f, closure::PlaceCloud> two_views(unsigned seed, const Eigen::Isometry3d& T,
                                                   const test::SceneOptions& o = {}) {
  return two_views_of(test::street_scene(seed, o), seed, T);
}

TEST(Icp, RecoversRandomTransformsWithinTheBasin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry3d T =
        pose(20 * u(rng), 2 * u(rng), 2 * u(rng), Eigen::Vector3d(3 * u(rng), 0.3 * u(rng), 3 * u(rng)));
    const auto [target_points, source] = two_views(100 + trial, T);
    const closure::TargetCloud target(target_points);
    // Start from the yaw a descriptor would give, off by up to 5 degrees.
    const double yaw_guess = closure::yaw_of(T) + 5 * M_PI / 180 * u(rng);
    const closure::Loop loop = closure::verify_candidate(target, source, {closure::yaw_rotation(yaw_guess)});
    SCOPED_TRACE(trial);
    EXPECT_EQ(loop.verdict, closure::Verdict::Accepted) << closure::to_string(loop.verdict)
        << " overlap " << loop.overlap << " rmse " << loop.rmse_m << " constraint " << loop.translation_constraint;
    EXPECT_LT((loop.T_query_match.translation() - T.translation()).norm(), 0.05);
    EXPECT_LT(rotation_error_deg(loop.T_query_match, T), 0.3);
  }
}

// On several threads (the starts, then the finalists, aligned apart; each query normal fitted
// once, by the first thread that needs it) verification gives the loop one thread gives, to the
// bit; so do the plane fits.
TEST(Icp, ThreadsGiveTheSameLoopAndNormals) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int accepted = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const Eigen::Isometry3d T =
        pose(30 * u(rng), 2 * u(rng), 2 * u(rng), Eigen::Vector3d(4 * u(rng), 0.3 * u(rng), 6 * u(rng)));
    const auto [target_points, source] = two_views(300 + trial, T);
    const closure::TargetCloud lazy(target_points), threaded(target_points);
    const double yaw = closure::yaw_of(T) + 5 * M_PI / 180 * u(rng);
    const std::vector<Eigen::Isometry3d> guesses = {closure::yaw_rotation(yaw),
                                                    closure::yaw_rotation(yaw + M_PI)};
    const closure::Loop one = closure::verify_candidate(lazy, source, guesses);
    const closure::Loop three = closure::verify_candidate(threaded, source, guesses, {}, nullptr, 3);
    SCOPED_TRACE(trial);
    EXPECT_EQ(three.verdict, one.verdict);
    EXPECT_TRUE(three.T_query_match.matrix() == one.T_query_match.matrix());
    EXPECT_EQ(three.overlap, one.overlap);
    EXPECT_EQ(three.rmse_m, one.rmse_m);
    EXPECT_EQ(three.iterations, one.iterations);
    accepted += one.verdict == closure::Verdict::Accepted;
    for (std::size_t i = 0; i < target_points.size(); ++i) {
      ASSERT_EQ(threaded.has_normal(int(i)), lazy.has_normal(int(i))) << i;
      ASSERT_TRUE(threaded.normal(int(i)) == lazy.normal(int(i))) << i;
    }
    // A place's classification with its plane fits on 3 threads (every few points only).
    const closure::TargetCloud fresh(target_points);
    const closure::PlaceCloud a = closure::to_place_cloud(fresh, 500, 0.9, 3);
    int fitted = 0;
    for (std::size_t i = 0; i < target_points.size(); ++i) fitted += fresh.normal_fitted(int(i));
    EXPECT_GT(fitted, 500);
    EXPECT_LT(std::size_t(fitted), target_points.size() / 2);  // an even subset only
    const closure::PlaceCloud b = closure::to_place_cloud(closure::TargetCloud(target_points), 500);
    EXPECT_EQ(a.structure, b.structure);
    EXPECT_TRUE(a.points == b.points);
  }
  EXPECT_GE(accepted, 4);  // mostly real alignments, not refusals
}

// The default convergence thresholds stop a stage once its steps are below the voxels' noise:
// against ICP that runs every stage to its 12 iterations (thresholds of 10 um and 1 urad,
// never met), it lands within a tenth of the 0.5 m voxels and 0.05 degrees, with the same
// overlap, within 6 cm of the truth, in under half the steps.
TEST(Icp, StagesEndWhenStepsFallBelowTheVoxelsNoise) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  closure::IcpConfig fine;
  fine.converged_translation_m = 1e-5;
  fine.converged_rotation_rad = 1e-6;
  int coarse_steps = 0, oracle_steps = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const Eigen::Isometry3d T = pose(10 * u(rng), 1 * u(rng), 1 * u(rng),
                                     Eigen::Vector3d(2 * u(rng), 0.2 * u(rng), 2 * u(rng)));
    const auto [target_points, source] = two_views(300 + trial, T);
    const closure::TargetCloud target(target_points);
    const Eigen::Isometry3d start = closure::yaw_rotation(closure::yaw_of(T));
    const closure::IcpResult coarse =
        closure::align_point_to_plane(source.points, target, start, {}, source.structure);
    const closure::IcpResult oracle =
        closure::align_point_to_plane(source.points, target, start, fine, source.structure);
    SCOPED_TRACE(trial);
    EXPECT_LT((coarse.T_target_source.translation() - oracle.T_target_source.translation()).norm(),
              0.05);
    EXPECT_LT(rotation_error_deg(coarse.T_target_source, oracle.T_target_source), 0.05);
    EXPECT_NEAR(coarse.overlap, oracle.overlap, 0.01);
    EXPECT_LT((coarse.T_target_source.translation() - T.translation()).norm(), 0.06);
    EXPECT_LT(coarse.iterations, oracle.iterations);
    coarse_steps += coarse.iterations;
    oracle_steps += oracle.iterations;
  }
  EXPECT_LT(coarse_steps, oracle_steps / 2);
}

TEST(Icp, YawGuessesCoverTheOppositeHeading) {
  // The descriptor's yaw is off by 180 degrees (a place seen the other way): the second guess
  // finds it.
  const Eigen::Isometry3d T = pose(178, 0.5, -0.5, Eigen::Vector3d(1.0, 0.1, -2.0));
  const auto [target_points, source] = two_views(31, T);
  const closure::TargetCloud target(target_points);
  Candidate c;
  c.yaw_rad = -2 * M_PI / 180;
  const closure::Loop loop = closure::verify_candidate(target, source, closure::yaw_guesses(c));
  EXPECT_EQ(loop.verdict, closure::Verdict::Accepted);
  EXPECT_LT((loop.T_query_match.translation() - T.translation()).norm(), 0.05);
  EXPECT_LT(rotation_error_deg(loop.T_query_match, T), 0.3);
}

TEST(Icp, BirdsEyeCandidatesSeedWithTheirMetricPoseFirst) {
  // A revisit 7 m along and 3 m aside, turned 120 degrees: the bird's-eye candidate's pose (a
  // cell off) is the first start, and the alignment from it is accepted.
  const Eigen::Isometry3d T = pose(120, 0.3, -0.4, Eigen::Vector3d(3.0, 0.1, 7.0));
  const auto [target_points, source] = two_views(37, T);
  const closure::TargetCloud target(target_points);
  Candidate c;
  c.yaw_rad = closure::yaw_of(T) + 2 * M_PI / 180;
  c.x_m = 3.6;
  c.z_m = 6.5;
  const std::vector<Eigen::Isometry3d> guesses = closure::yaw_guesses(c);
  ASSERT_EQ(guesses.size(), 3u);
  EXPECT_TRUE(guesses[0].translation().isApprox(Eigen::Vector3d(3.6, 0.0, 6.5)));
  EXPECT_TRUE(guesses[0].linear().isApprox(closure::yaw_rotation(c.yaw_rad).linear()));
  EXPECT_TRUE(guesses[1].isApprox(closure::yaw_rotation(c.yaw_rad)));
  const closure::Loop loop = closure::verify_candidate(target, source, {guesses[0]});
  EXPECT_EQ(loop.verdict, closure::Verdict::Accepted) << closure::to_string(loop.verdict);
  EXPECT_LT((loop.T_query_match.translation() - T.translation()).norm(), 0.05);
  EXPECT_LT(rotation_error_deg(loop.T_query_match, T), 0.3);
}

TEST(Icp, CorridorOfBareFacadesIsRefusedAsDegenerate) {
  test::SceneOptions corridor;
  corridor.poles_and_boxes = false;
  corridor.facade_recesses = false;
  const Eigen::Isometry3d T = pose(3, 0, 0, Eigen::Vector3d(0.5, 0, 4.0));
  const auto [target_points, source] = two_views(5, T, corridor);
  const closure::Loop loop =
      closure::verify_candidate(closure::TargetCloud(target_points), source, {closure::yaw_rotation(0.0)});
  EXPECT_EQ(loop.verdict, closure::Verdict::Degenerate) << closure::to_string(loop.verdict)
      << " constraint " << loop.translation_constraint;
  // The same street with poles and parked cars is constrained.
  const auto [t2, s2] = two_views(5, T);
  const closure::Loop ok = closure::verify_candidate(closure::TargetCloud(t2), s2, {closure::yaw_rotation(0.0)});
  EXPECT_EQ(ok.verdict, closure::Verdict::Accepted);
  EXPECT_GT(ok.translation_constraint, 3 * loop.translation_constraint)
      << ok.translation_constraint << " vs the corridor's " << loop.translation_constraint;
}

TEST(Icp, NearlyEmptyAndUnrelatedScansAreRefused) {
  const auto [target_points, source] = two_views(8, Eigen::Isometry3d::Identity());
  const closure::TargetCloud target(target_points);
  closure::PlaceCloud few;
  few.points.assign(source.points.begin(), source.points.begin() + 40);
  few.structure = 40;
  EXPECT_EQ(closure::verify_candidate(target, few, {closure::yaw_rotation(0.0)}).verdict, closure::Verdict::FewPoints);
  EXPECT_EQ(closure::verify_candidate(closure::TargetCloud(Points3f(target_points.begin(),
                                                                    target_points.begin() + 40)),
                                      source, {closure::yaw_rotation(0.0)})
                .verdict,
            closure::Verdict::FewPoints);
  // A small place (just over min_points, screened on every 4th) verifies from guesses off
  // along the track.
  closure::PlaceCloud small;
  for (std::size_t i = 0; i < source.structure; i += source.structure / 160) small.points.push_back(source.points[i]);
  small.structure = small.points.size();
  ASSERT_GE(small.points.size(), 160u);
  for (double along : {-3.0, -1.5, 1.5, 3.0}) {
    Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
    guess.translation().z() = along;
    const closure::Loop loop = closure::verify_candidate(target, small, {guess});
    EXPECT_EQ(loop.verdict, closure::Verdict::Accepted) << along << " m: " << to_string(loop.verdict);
    EXPECT_LT(loop.T_query_match.translation().norm(), 0.3) << along;
  }
  // Another street altogether (different poles, cars, facade offsets), from every heading.
  for (unsigned seed : {9u, 10u, 11u}) {
    test::SceneOptions other;
    other.half_width_m = 4.5;  // a narrow lane: its facades fit neither of the query's
    const auto [unused, foreign] = two_views(seed, pose(0, 0, 0, Eigen::Vector3d(0, 0, 0)), other);
    const closure::Loop loop = closure::verify_candidate(target, foreign, {closure::yaw_rotation(0.0), closure::yaw_rotation(M_PI / 2), closure::yaw_rotation(M_PI), closure::yaw_rotation(-M_PI / 2)});
    EXPECT_NE(loop.verdict, closure::Verdict::Accepted) << seed << " overlap " << loop.overlap
        << " rmse " << loop.rmse_m;
  }
}

TEST(Icp, ScoreMatchesBruteForceNearestNeighbours) {
  const Eigen::Isometry3d T = pose(4, 1, 0, Eigen::Vector3d(0.4, 0.0, 0.7));
  const auto [target_points, source] = two_views(12, T);
  const closure::TargetCloud target(target_points);
  closure::IcpConfig config;
  const closure::IcpResult r = closure::score_alignment(source.points, target, T, config);
  int inliers = 0;
  double sum = 0;
  for (const Eigen::Vector3f& s : source.points) {
    const Eigen::Vector3f p = (T * s.cast<double>()).cast<float>();
    float best = 1e30f;
    std::size_t at = 0;
    for (std::size_t j = 0; j < target_points.size(); ++j) {
      if ((p - target_points[j]).squaredNorm() < best) best = (p - target_points[j]).squaredNorm(), at = j;
    }
    if (best > float(config.inlier_distance_m * config.inlier_distance_m)) continue;
    ++inliers;
    const double along = target.normal(int(at)).dot(p - target_points[at]);
    sum += target.has_normal(int(at)) ? along * along : best;
  }
  EXPECT_EQ(r.inliers, inliers);
  EXPECT_NEAR(r.rmse_m, std::sqrt(sum / inliers), 1e-4);
  EXPECT_NEAR(r.overlap, double(inliers) / source.points.size(), 1e-12);
}

TEST(PlaceCloud, OnePointPerVoxelAtItsCentroidWhateverTheOrder) {
  Points3f pts = test::street_scene(3);
  pts.push_back(Eigen::Vector3f(std::nanf(""), 0, 0));
  pts.push_back(Eigen::Vector3f(1e30f, 0, 0));  // far, but no overflow
  const double voxel = 0.5;
  const Points3f cloud = closure::voxel_downsample(pts, voxel);
  std::set<std::tuple<long, long, long>> voxels;
  for (const Eigen::Vector3f& p : pts) {
    if (!p.allFinite() || p.norm() > 1e6f) continue;
    voxels.insert({long(std::floor(p.x() / voxel)), long(std::floor(p.y() / voxel)),
                   long(std::floor(p.z() / voxel))});
  }
  EXPECT_EQ(cloud.size(), voxels.size() + 1);  // + the far point's voxel
  std::size_t inside = 0;
  for (const Eigen::Vector3f& c : cloud) {
    inside += voxels.count({long(std::floor(c.x() / voxel)), long(std::floor(c.y() / voxel)),
                            long(std::floor(c.z() / voxel))});
  }
  EXPECT_EQ(inside, voxels.size());
  // Brute-force centroids of a few voxels.
  for (std::size_t i = 0; i < cloud.size(); i += 97) {
    const Eigen::Vector3f& c = cloud[i];
    const auto cell = [&](const Eigen::Vector3f& p) {
      return std::make_tuple(long(std::floor(p.x() / voxel)), long(std::floor(p.y() / voxel)),
                             long(std::floor(p.z() / voxel)));
    };
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (const Eigen::Vector3f& p : pts) {
      if (p.allFinite() && cell(p) == cell(c)) sum += p.cast<double>(), ++n;
    }
    ASSERT_GT(n, 0);
    EXPECT_LT((sum / n - c.cast<double>()).norm(), 1e-4);
  }
  // Another input order: the same voxels (in another order).
  Points3f shuffled = pts;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(4));
  Points3f again = closure::voxel_downsample(shuffled, voxel), sorted = cloud;
  const auto less = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return std::make_tuple(a.x(), a.y(), a.z()) < std::make_tuple(b.x(), b.y(), b.z());
  };
  ASSERT_EQ(again.size(), cloud.size());
  std::sort(again.begin(), again.end(), less);
  std::sort(sorted.begin(), sorted.end(), less);
  for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_LT((again[i] - sorted[i]).norm(), 1e-4f);
  closure::CloudConfig capped;
  capped.max_points = 500;
  EXPECT_EQ(closure::voxel_cloud(pts, capped).size(), 500u);
}

TEST(TargetCloud, NearestMatchesBruteForceAndNormalsArePlaneNormals) {
  const Points3f pts = closure::voxel_cloud(test::street_scene(21));
  const closure::TargetCloud target(pts);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-20.f, 20.f);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3f q(u(rng), u(rng) / 8, u(rng));
    float best = 1e30f;
    for (const Eigen::Vector3f& p : pts) best = std::min(best, (p - q).squaredNorm());
    float d2 = -1;
    const int j = target.nearest(q, 1e30f, &d2);
    ASSERT_GE(j, 0);
    EXPECT_FLOAT_EQ(d2, best);
    EXPECT_EQ(target.nearest(q, best * 0.99f, nullptr), best > 0 ? -1 : j);
    // A hint (any point, the answer itself, none, out of range) changes nothing, bounded or not.
    std::uniform_int_distribution<int> any(-1, int(pts.size()));
    for (const int hint : {any(rng), any(rng), j, -1, int(pts.size()) + 5}) {
      for (const float bound : {1e30f, best * 4.f, best, best * 0.99f, 0.25f}) {
        float unhinted_d2 = -1, hinted_d2 = -1;
        const int a = target.nearest(q, bound, &unhinted_d2);
        ASSERT_EQ(target.nearest(q, bound, &hinted_d2, hint), a) << "hint " << hint << " bound " << bound;
        if (a >= 0) {
          EXPECT_EQ(hinted_d2, unhinted_d2);
        }
      }
    }
  }
  // Normals against a brute-force plane fit over the 12 nearest points within 3 m.
  int compared = 0;
  for (std::size_t i = 0; i < pts.size(); i += 7) {
    std::vector<std::pair<float, std::size_t>> by_distance;
    for (std::size_t k = 0; k < pts.size(); ++k) by_distance.push_back({(pts[k] - pts[i]).squaredNorm(), k});
    std::partial_sort(by_distance.begin(), by_distance.begin() + 12, by_distance.end());
    std::vector<Eigen::Vector3d> near;
    for (int k = 0; k < 12; ++k) {
      if (by_distance[std::size_t(k)].first <= 9.f) near.push_back(pts[by_distance[std::size_t(k)].second].cast<double>());
    }
    if (near.size() < 5) {
      EXPECT_FALSE(target.has_normal(int(i)));
      continue;
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : near) mean += p / double(near.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const auto& p : near) scatter += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);  // the iterative solver
    const Eigen::Vector3d ev = eig.eigenvalues();
    const double planarity = ev[0] / ev[1];
    if (std::abs(planarity - 0.25) < 1e-3) continue;  // at the threshold either answer is right
    ASSERT_EQ(target.has_normal(int(i)), planarity <= 0.25) << i;
    if (!target.has_normal(int(i))) continue;
    EXPECT_GT(std::abs(target.normal(int(i)).cast<double>().dot(eig.eigenvectors().col(0))), 1 - 1e-6) << i;
    ++compared;
  }
  EXPECT_GT(compared, 100);
  // Ground points (y = 1.65, away from facades and objects) have vertical normals.
  int ground = 0, vertical = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (std::abs(pts[i].y() - 1.65f) > 0.05f || std::abs(pts[i].x()) > 5 || !target.has_normal(int(i))) continue;
    ++ground;
    vertical += std::abs(target.normal(int(i)).y()) > 0.98f;
  }
  ASSERT_GT(ground, 50);
  EXPECT_GT(vertical, ground * 9 / 10);
  EXPECT_THROW(closure::TargetCloud(Points3f{Eigen::Vector3f(NAN, 0, 0)}), std::invalid_argument);
  EXPECT_EQ(closure::TargetCloud(Points3f{}).nearest(Eigen::Vector3f::Zero(), 1.f, nullptr), -1);
}

// The bounds ICP searches with most (a last correspondence nearby, the fine stages' and the
// score's distances) are answered by a grid of columns, larger ones by the tree: near the
// surfaces, on and just off cell borders, below the cloud's corner, in a cloud far from the
// origin, each answer is the brute-force nearest within the bound.
TEST(TargetCloud, NearestWithinSmallBoundsIsTheBruteForceNearest) {
  const Points3f street = closure::voxel_cloud(test::street_scene(5));
  Points3f far = street;  // beyond the grid's reach: the tree answers alone
  for (Eigen::Vector3f& p : far) p += Eigen::Vector3f(4000.f, -50.f, 3000.f);
  std::mt19937 rng(11);
  std::normal_distribution<float> jitter(0.f, 0.4f);
  std::uniform_real_distribution<float> bound_m(0.f, 2.5f);
  for (const Points3f* pts : std::vector<const Points3f*>{&street, &far}) {
    const closure::TargetCloud target(*pts);
    std::uniform_int_distribution<std::size_t> pick(0, pts->size() - 1);
    // The grid starts at the cloud's corner; its cells are a whole number of half metres.
    Eigen::Vector3f lo = (*pts)[0];
    for (const Eigen::Vector3f& p : *pts) lo = lo.cwiseMin(p);
    const auto on_border = [](float v, float origin) {
      return origin + 0.5f * std::round((v - origin) / 0.5f);
    };
    int found = 0, empty = 0;
    for (int i = 0; i < 3000; ++i) {
      Eigen::Vector3f q =
          (*pts)[pick(rng)] + Eigen::Vector3f(jitter(rng), jitter(rng), jitter(rng));
      // On a border, just below one, below the grid's corner.
      if (i % 3 == 0) q.x() = on_border(q.x(), lo.x());
      if (i % 5 == 0) q.z() = std::nextafter(on_border(q.z(), lo.z()), -1e9f);
      if (i % 11 == 0) q.x() = lo.x() - std::abs(jitter(rng));
      // Every other bound up to 5 m: the grid answers up to 2 m, the tree beyond (ICP's 4 m).
      const float r = i % 7 == 0 ? 0.f : (i % 2 == 0 ? 1.f : 2.f) * bound_m(rng);
      const float bound = r * r;
      float best = std::numeric_limits<float>::infinity();
      for (const Eigen::Vector3f& p : *pts) best = std::min(best, (q - p).squaredNorm());
      float d2 = -1;
      const int j = target.nearest(q, bound, &d2, i % 2 == 0 ? int(pick(rng)) : -1);
      if (best > bound * (1 + 1e-6f)) {
        ASSERT_EQ(j, -1) << "query " << i << " bound " << bound << " nearest " << best;
        ++empty;
        continue;
      }
      if (best < bound * (1 - 1e-6f)) {
        ASSERT_GE(j, 0) << "query " << i << " bound " << bound << " nearest " << best;
      }
      if (j < 0) continue;  // at the bound's edge, either answer is right
      EXPECT_FLOAT_EQ(d2, (q - (*pts)[std::size_t(j)]).squaredNorm());
      EXPECT_LE(d2, best * (1 + 1e-6f)) << "query " << i;
      // The tree (an unbounded search) finds the same point at the same distance, to the bit.
      float tree_d2 = -1;
      if (target.nearest(q, std::numeric_limits<float>::max(), &tree_d2) == j) {
        EXPECT_EQ(d2, tree_d2) << "query " << i;
      }
      ++found;
    }
    EXPECT_GT(found, 1000);
    EXPECT_GT(empty, 300);
  }
}

TEST(QueryPlacement, IsWhereTheAlignmentPutsTheQuery) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-30, 30), a(-180, 180), small(-8, 8);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Isometry3d T_world_query =
        pose(a(rng), small(rng), small(rng), {u(rng), u(rng), u(rng)});
    const Eigen::Isometry3d T_world_place =
        pose(a(rng), small(rng), small(rng), {u(rng), u(rng), u(rng)});
    closure::Loop loop;
    loop.T_query_match = T_world_query.inverse() * T_world_place;
    loop.overlap = 0.4;
    const closure::QueryPlacement p = closure::placement(loop, T_world_place, 3);
    EXPECT_LT((p.position - T_world_query.translation()).norm(), 1e-9);
    EXPECT_EQ(p.frame, 3);
    EXPECT_EQ(p.overlap, 0.4);
  }
}

TEST(QueryPlacement, AnotherPlaceAsWellAlignedElsewhereMakesItAmbiguous) {
  closure::VerifyConfig config;  // rival_place_share 1, rival_place_m 3, screen_min_overlap 0.25
  const closure::QueryPlacement accepted{Eigen::Vector3d(10, 0, 5), 0, 0.40};
  const auto rival = [&](Eigen::Vector3d offset, int frame, double overlap) {
    return closure::placed_elsewhere(accepted, {{accepted.position + offset, frame, overlap}},
                                     config);
  };
  EXPECT_TRUE(rival({3.1, 0, 0}, 0, 0.40));   // as well aligned, just beyond 3 m
  EXPECT_TRUE(rival({0, 0, -6}, 0, 0.55));    // better aligned, 6 m along the track
  EXPECT_FALSE(rival({2.9, 0, 0}, 0, 0.55));  // better, but where the accepted one puts it
  EXPECT_FALSE(rival({0, 0, 6}, 0, 0.39));    // elsewhere, but worse aligned
  EXPECT_FALSE(rival({0, 0, 6}, 1, 0.60));    // a frame not tied to the accepted place's
  EXPECT_FALSE(closure::placed_elsewhere({accepted.position, -1, 0.4},
                                         {{accepted.position, -1, 0.9}}, config));
  EXPECT_FALSE(closure::placed_elsewhere(accepted, {}, config));
  // A start that screening left coarse (under screen_min_overlap) is no evidence.
  const closure::QueryPlacement weak{accepted.position, 0, 0.25};
  EXPECT_FALSE(closure::placed_elsewhere(
      weak, {{weak.position + Eigen::Vector3d(9, 0, 0), 0, 0.24}}, config));
  EXPECT_TRUE(closure::placed_elsewhere(weak, {{weak.position + Eigen::Vector3d(9, 0, 0), 0, 0.26}},
                                        config));
  // One rival among agreeing ones is enough; 0 m turns the test off.
  const std::vector<closure::QueryPlacement> others = {
      {accepted.position + Eigen::Vector3d(1, 0, 0), 0, 0.5},
      {accepted.position + Eigen::Vector3d(0, 0, 8), 0, 0.5}};
  EXPECT_TRUE(closure::placed_elsewhere(accepted, others, config));
  config.rival_place_m = 0;
  EXPECT_FALSE(closure::placed_elsewhere(accepted, others, config));
  config.rival_place_m = 3;
  config.rival_place_share = 1.3;  // 0.5 is under 1.3 x 0.4
  EXPECT_FALSE(closure::placed_elsewhere(accepted, others, config));
}

// An alignment slid along the street: the place's near structure fits better where it
// belongs, 4 or 6 m along the track, than where it was put.
TEST(SlideRatio, BelowOneAtTheTruePoseAboveWhereTheAlignmentSlid) {
  for (const auto& [seed, yaw_deg] : {std::pair{41u, 6.0}, {42u, 35.0}, {43u, 180.0}}) {
    // (Along the query's track: at 35 and 180 degrees the place's own axis is another.)
    const Eigen::Isometry3d T = pose(yaw_deg, 0, 0, Eigen::Vector3d(1.0, 0.0, 2.0));
    const auto [target_points, place] = two_views(seed, T);
    const closure::TargetCloud query(target_points);
    SCOPED_TRACE(seed);
    EXPECT_LT(closure::slide_ratio(query, place, T), 0.95);
    for (double slid : {-6.0, -4.0, 4.0, 6.0}) {
      Eigen::Isometry3d wrong = T;
      wrong.translation().z() += slid;
      EXPECT_GT(closure::slide_ratio(query, place, wrong), 1.1) << slid << " m";
    }
  }
  // Too little structure near the query: no verdict either way.
  const auto [target_points, place] = two_views(41, Eigen::Isometry3d::Identity());
  Eigen::Isometry3d away = Eigen::Isometry3d::Identity();
  away.translation().x() = 200;
  EXPECT_TRUE(std::isnan(closure::slide_ratio(closure::TargetCloud(target_points), place, away)));
}

// A street whose near stretch is bare facades and whose poles and parked cars are all over
// 20 m away: the far objects pin the alignment, the near structure would fit as well anywhere
// along the track, so the alignment is refused as ambiguous unless the slide test is off.
TEST(SlideRatio, NearStructureThatFitsAnywhereAlongTheTrackIsAmbiguous) {
  test::SceneOptions bare;
  bare.poles_and_boxes = false;
  bare.facade_recesses = false;
  bare.length_m = 40;
  bare.points = 12000;
  Points3f all = test::street_scene(51, bare);
  for (unsigned seed : {52u, 53u, 54u}) {
    for (const Eigen::Vector3f& p : test::street_scene(seed)) {
      if (std::abs(p.z()) > 20 && std::abs(p.x()) < 8.5) all.push_back(p);
    }
  }
  const Eigen::Isometry3d T = pose(2, 0, 0, Eigen::Vector3d(0.5, 0, 1.0));
  const auto [target_points, place] = two_views_of(all, 51, T);
  const closure::TargetCloud query(target_points);
  closure::VerifyConfig config;
  config.slide_share = 0.97;  // the bare facades score alike at every shift, up to sampling
  EXPECT_GT(closure::slide_ratio(query, place, T, config), 0.97);
  EXPECT_EQ(closure::verify_candidate(query, place, {closure::yaw_rotation(0.0)}, config).verdict,
            closure::Verdict::Ambiguous);
  config.slide_share = 0;
  const closure::Loop off =
      closure::verify_candidate(query, place, {closure::yaw_rotation(0.0)}, config);
  EXPECT_EQ(off.verdict, closure::Verdict::Accepted) << closure::to_string(off.verdict);
  EXPECT_LT((off.T_query_match.translation() - T.translation()).norm(), 0.1);
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

// The loop covariance model: larger along the track for the opposite heading, across it for
// a lateral offset, and in a direction the aligned surfaces leave weak; always positive
// definite.
TEST(LoopCovariance, GrowsWithTheViewpointChangeAndWeakGeometry) {
  closure::Loop same;
  same.translation_information = Eigen::Matrix3d::Identity() / 3.0;
  const closure::Covariance6 base = closure::loop_covariance(same);
  EXPECT_NEAR(std::sqrt(base(0, 0)), std::hypot(0.2, 0.1), 1e-9);
  EXPECT_NEAR(std::sqrt(base(2, 2)), std::hypot(0.2, 0.1), 1e-9);
  closure::Loop reverse = same;
  reverse.T_query_match = closure::yaw_rotation(M_PI);
  const closure::Covariance6 r = closure::loop_covariance(reverse);
  EXPECT_NEAR(std::sqrt(r(2, 2)), std::hypot(1.8, 0.1), 1e-9);  // along the track
  EXPECT_NEAR(r(0, 0), base(0, 0), 1e-9);                       // across: as the same heading
  closure::Loop aside = same;
  aside.T_query_match.translation().x() = 3.5;
  EXPECT_NEAR(std::sqrt(closure::loop_covariance(aside)(0, 0)), std::hypot(0.2 + 0.3 * 3.5, 0.1), 1e-9);
  closure::Loop corridor = same;  // facades only: nothing faces along z
  corridor.translation_information = Eigen::Vector3d(0.6, 0.39, 0.01).asDiagonal();
  const closure::Covariance6 c = closure::loop_covariance(corridor);
  EXPECT_GT(c(2, 2), 5 * c(0, 0));
  for (const closure::Covariance6& m : {base, r, c}) {
    EXPECT_EQ(Eigen::LLT<closure::Covariance6>(m).info(), Eigen::Success);
  }
}

}  // namespace
}  // namespace loopscan
