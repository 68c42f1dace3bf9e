// The database on a simulated drive: relative yaw against ground truth at true revisits, and
// the online (streaming) query against the offline difference-matrix evaluation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/lane_query.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/pipeline/recognizer.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/sim/simulated_places.hpp"
#include "loopscan/sim/vo_simulator.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan {
namespace {

const sim::SimulatedPlaces& city(sim::Season season) {
  static const sim::SimulatedPlaces summer = sim::simulate_places(
      sim::make_builtin_trajectory("city"), sim::Season::Summer, 7, 100, Method::ScanContext, 2);
  static const sim::SimulatedPlaces winter = sim::simulate_places(
      sim::make_builtin_trajectory("city"), sim::Season::Winter, 7, 101, Method::ScanContext, 2);
  return season == sim::Season::Summer ? summer : winter;
}

struct OnlineRun {
  std::vector<eval::QueryMatch> matches;
  std::vector<std::size_t> best;  // per query, SIZE_MAX when nothing matched
};

// Queries every place of `queries` against `db`, one at a time; `grow`: add each query to the
// database after it was answered (streaming, same session).
OnlineRun run_queries(const sim::SimulatedPlaces& queries, Database& db, QueryOptions opt,
                      bool grow, bool mask_around_self) {
  OnlineRun run;
  for (std::size_t i = 0; i < queries.places.size(); ++i) {
    if (mask_around_self) {
      opt.accept = outside_band(i, 100);
    }
    const auto got = db.query(queries.places[i], 1, opt);
    if (grow) db.add({0, queries.keyframe_ids[i]}, queries.places[i]);
    const int q = static_cast<int>(i);
    if (got.empty()) {
      run.matches.push_back({q, 0, std::numeric_limits<double>::infinity()});
      run.best.push_back(SIZE_MAX);
    } else {
      run.matches.push_back({q, static_cast<int>(got[0].index), got[0].distance});
      run.best.push_back(got[0].index);
    }
  }
  return run;
}

// Ground truth: the place keyframe's forward axis in the query camera frame, yaw about -y.
double gt_yaw(const Eigen::Isometry3d& query, const Eigen::Isometry3d& place) {
  const Eigen::Vector3d f = query.linear().transpose() * place.linear() * Eigen::Vector3d::UnitZ();
  return std::atan2(-f.x(), f.z());
}

TEST(DatabaseSim, YawAtTrueRevisitsMatchesGroundTruth) {
  const auto& s = city(sim::Season::Summer);
  Database db;
  QueryOptions opt;
  opt.exclude_recent = 100;
  std::vector<double> errors_deg;
  for (std::size_t i = 0; i < s.places.size(); ++i) {
    const auto got = db.query(s.places[i], 1, opt);
    db.add({0, s.keyframe_ids[i]}, s.places[i]);
    if (got.empty()) continue;
    const std::size_t j = got[0].index;
    if ((s.T_world_cam[i].translation() - s.T_world_cam[j].translation()).norm() > 5.0) continue;
    const double e =
        std::remainder(got[0].yaw_rad - gt_yaw(s.T_world_cam[i], s.T_world_cam[j]), 2 * M_PI);
    errors_deg.push_back(std::abs(e) * 180 / M_PI);
  }
  ASSERT_GE(errors_deg.size(), 50u);
  std::sort(errors_deg.begin(), errors_deg.end());
  const double median = errors_deg[errors_deg.size() / 2];
  const double p75 = errors_deg[errors_deg.size() * 3 / 4];
  std::printf("yaw error at %zu true revisits: median %.2f deg, p75 %.2f deg, max %.2f deg\n",
              errors_deg.size(), median, p75, errors_deg.back());
  // Most revisits are within half a sector; the tail is symmetric streets (180 deg) and
  // crossings seen from perpendicular directions, where the scans share little.
  EXPECT_LT(median, 3.0);
  EXPECT_LT(p75, 8.0);
}

// How well an indexed run keeps the exact run's top-1 where it matters: of the queries whose
// exact best place is a true revisit (within the protocol's 10 m), how many have the same best
// place.
struct Kept {
  int true_best = 0, kept = 0;
};
Kept kept_true_best(const OnlineRun& exact, const OnlineRun& indexed,
                    const std::vector<Eigen::Vector3d>& query_positions,
                    const std::vector<Eigen::Vector3d>& map_positions) {
  const double threshold = eval::same_session_protocol().threshold_m;
  Kept k;
  for (std::size_t i = 0; i < exact.best.size(); ++i) {
    const std::size_t j = exact.best[i];
    if (j == SIZE_MAX || (query_positions[i] - map_positions[j]).norm() > threshold) continue;
    ++k.true_best;
    k.kept += indexed.best[i] == j;
  }
  return k;
}

// The brute-force oracle of an exact query: the difference-matrix row of the query (every
// place's two distance components, PlaceMatcher's exact path), each component z-scored over
// the row's eligible places (Matlab's normalize: n - 1), fused with w_s, and the smallest.
struct OracleBest {
  std::size_t index = SIZE_MAX;
  double distance = std::numeric_limits<double>::infinity();
};
OracleBest oracle_best(const PlaceMatcher& matcher, const Signature& query,
                       const std::function<bool(std::size_t)>& eligible, double w_s) {
  Eigen::MatrixXd rows;
  matcher.distances(query, rows);
  std::vector<std::size_t> cols;
  for (Eigen::Index j = 0; j < rows.cols(); ++j) {
    if (eligible(static_cast<std::size_t>(j))) cols.push_back(static_cast<std::size_t>(j));
  }
  OracleBest best;
  if (cols.empty()) return best;
  double mean[2] = {0, 0}, sd[2] = {0, 0};
  for (int c = 0; c < 2; ++c) {
    for (std::size_t j : cols) mean[c] += rows(c, static_cast<Eigen::Index>(j));
    mean[c] /= static_cast<double>(cols.size());
    double ss = 0;
    for (std::size_t j : cols) ss += std::pow(rows(c, static_cast<Eigen::Index>(j)) - mean[c], 2);
    sd[c] = cols.size() > 1 ? std::sqrt(ss / static_cast<double>(cols.size() - 1)) : 0.0;
  }
  for (std::size_t j : cols) {
    double d = 0;
    for (int c = 0; c < 2; ++c) {
      const double z = sd[c] > 0 ? (rows(c, static_cast<Eigen::Index>(j)) - mean[c]) / sd[c] : 0;
      d += (c == 0 ? w_s : 1.0) * z;
    }
    if (d < best.distance) best = {j, d};
  }
  return best;
}

TEST(DatabaseSim, ExactQueriesAreTheOracleAndIndexedOnesKeepTheirBestPlace) {
  // Same season (the map queried with its own places, 100 keyframes masked) and cross season
  // (winter against the summer map): every exact query against the brute-force oracle, then
  // the indexed search judged by the exact search's top-1.
  for (const bool cross : {false, true}) {
    SCOPED_TRACE(cross ? "winter vs summer" : "summer vs summer");
    const auto& map = city(sim::Season::Summer);
    const auto& queries = city(cross ? sim::Season::Winter : sim::Season::Summer);
    Database db;
    const auto matcher = make_matcher(Method::ScanContext, Precision::Float);
    for (std::size_t i = 0; i < map.places.size(); ++i) {
      db.add({0, map.keyframe_ids[i]}, map.places[i]);
      matcher->add(map.places[i].signature);
    }
    QueryOptions exact, indexed;
    exact.retrieval = Retrieval::Exact;
    const OnlineRun a = run_queries(queries, db, exact, false, !cross);
    const OnlineRun b = run_queries(queries, db, indexed, false, !cross);
    double worst = 0;
    int answered = 0;
    for (std::size_t i = 0; i < queries.places.size(); ++i) {
      const auto eligible = [&](std::size_t j) { return cross || (i > j ? i - j : j - i) >= 100; };
      const OracleBest want = oracle_best(*matcher, queries.places[i].signature, eligible,
                                          DatabaseConfig{}.structure_weight);
      ASSERT_EQ(a.best[i], want.index) << "query " << i;
      if (want.index == SIZE_MAX) continue;
      ++answered;
      worst = std::max(worst, std::abs(a.matches[i].distance - want.distance));
    }
    EXPECT_GT(answered, 500);
    EXPECT_LE(worst, 1e-9);
    const Kept k = kept_true_best(a, b, queries.positions(), map.positions());
    eval::PlaceEvaluationOptions off;
    off.protocol = cross ? eval::cross_session_protocol() : eval::same_session_protocol();
    std::vector<Signature> query_signatures, map_signatures;
    for (const PlaceDescriptor& d : queries.places) query_signatures.push_back(d.signature);
    for (const PlaceDescriptor& d : map.places) map_signatures.push_back(d.signature);
    const auto auc = [&](const OnlineRun& run) {
      return eval::evaluate_matches(run.matches, queries.positions(), map.positions(), off.protocol)
          .auc;
    };
    std::printf(
        "%s: exact = oracle (worst %.2e) on %d queries; indexed keeps %d of the %d true "
        "best places of exact search; AUC offline (whole rows) %.4f, exact %.4f, indexed "
        "%.4f\n",
        cross ? "winter vs summer" : "summer vs summer", worst, answered, k.kept, k.true_best,
        eval::evaluate_places(query_signatures, map_signatures, queries.positions(),
                              map.positions(), off)
            .pr.auc,
        auc(a), auc(b));
    ASSERT_GT(k.true_best, 100);
    // Measured: 977 of 977 across seasons; 256 of 302 (0.85) within the season, where the
    // lateral versions bring reverse drives into reach of places the index does not propose.
    EXPECT_GE(k.kept, (cross ? 0.99 : 0.8) * k.true_best);
  }
}

TEST(DatabaseSim, StreamingExactQueriesAreTheOracleAndIndexedOnesKeepTheirBestPlace) {
  // The map grows as the drive goes, the 99 places added last ignored: each exact query against
  // the oracle over the places before those, then the indexed run judged by the exact one.
  const auto& s = city(sim::Season::Summer);
  QueryOptions exact, indexed;
  exact.retrieval = Retrieval::Exact;
  exact.exclude_recent = indexed.exclude_recent = 99;
  Database da, db;
  const OnlineRun a = run_queries(s, da, exact, true, false);
  const OnlineRun b = run_queries(s, db, indexed, true, false);
  const auto matcher = make_matcher(Method::ScanContext, Precision::Float);
  for (const PlaceDescriptor& p : s.places) matcher->add(p.signature);
  double worst = 0;
  for (std::size_t i = 0; i < s.places.size(); ++i) {
    const OracleBest want = oracle_best(
        *matcher, s.places[i].signature, [&](std::size_t j) { return j + 99 < i; },
        DatabaseConfig{}.structure_weight);
    ASSERT_EQ(a.best[i], want.index) << "query " << i;
    if (want.index != SIZE_MAX)
      worst = std::max(worst, std::abs(a.matches[i].distance - want.distance));
  }
  EXPECT_LE(worst, 1e-9);
  eval::Protocol causal = eval::same_session_protocol();
  causal.past_only = true;
  const double auc_exact =
      eval::evaluate_matches(a.matches, s.positions(), s.positions(), causal).auc;
  const double auc_indexed =
      eval::evaluate_matches(b.matches, s.positions(), s.positions(), causal).auc;
  const Kept k = kept_true_best(a, b, s.positions(), s.positions());
  std::printf(
      "streaming: exact = oracle (worst %.2e), AUC %.4f; indexed AUC %.4f, keeps %d of "
      "the %d true best places of exact search\n",
      worst, auc_exact, auc_indexed, k.kept, k.true_best);
  ASSERT_GT(k.true_best, 100);
  // Measured: 144 of 168 (0.86; docs/database.md: the indexed search misses more true places
  // when the lateral versions bring reverse drives into reach).
  EXPECT_GE(k.kept, 0.8 * k.true_best);
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

// Forward-only and two-sided scans (and a reset in the middle, which ends the waiting
// keyframes' map): the online recognizer describes the same places as the offline tool, in the
// same order, and answers what querying the map before each place joined it answers.
// Param: (lookahead_m, lane_offset_m); lane versions need the camera frame.
class RecognizerStreaming : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(RecognizerStreaming, EqualsDescribeThenQuery) {
  const sim::Trajectory route = sim::make_builtin_trajectory("short");
  const std::vector<int> keyframes = sim::select_keyframes(route);
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::VoOutput vo =
      sim::simulate_vo(route, keyframes, world, sim::Conditions::for_season(sim::Season::Summer),
                       sim::StereoCamera{}, sim::VoSimConfig{});
  const int reset_id = vo.poses[vo.poses.size() / 2].id;
  const auto [lookahead, lane] = GetParam();
  SequenceOptions options = SequenceOptions::make(Method::ScanContext, Mode::Default);
  options.imitation.lookahead_m = lookahead;
  options.reset_ids = {reset_id};
  if (lane != 0) options.descriptors.scan_context.frame = DescriptorFrame::Camera;
  const SequenceSignatures offline = describe_sequence(vo.poses, vo.points, options);
  std::vector<SequenceSignatures> lanes;  // the same places described from the next lanes
  for (const double side : {-1.0, 1.0}) {
    if (lane == 0) break;
    SequenceOptions o = options;
    o.descriptors.scan_context.lateral_offset_m = side * lane;
    lanes.push_back(describe_sequence(vo.poses, vo.points, o));
  }

  RecognizerConfig config = RecognizerConfig::make(Method::ScanContext);
  config.imitation.lookahead_m = lookahead;
  config.descriptors.scan_context.frame = options.descriptors.scan_context.frame;
  config.lane_offset_m = lane;
  config.k = 3;
  Recognizer recognizer(config);
  Database replay(config.database);
  std::size_t described = 0;
  auto check = [&](const std::vector<KeyframeResult>& results) {
    for (const KeyframeResult& r : results) {
      ASSERT_LT(described, offline.signatures.size());
      EXPECT_EQ(offline.keyframe_ids[described], r.keyframe);
      const PlaceDescriptor place{offline.signatures[described], offline.frames[described]};
      std::vector<PlaceDescriptor> versions;
      for (const SequenceSignatures& l : lanes) {
        versions.push_back({l.signatures[described], l.frames[described]});
      }
      const auto want = query_with_lane_versions(replay, place, versions, config.k, config.query);
      replay.add({0, r.keyframe}, place);
      ASSERT_EQ(r.matches.size(), want.size()) << "keyframe " << r.keyframe;
      for (std::size_t j = 0; j < want.size(); ++j) {
        EXPECT_EQ(r.matches[j].index, want[j].index);
        EXPECT_DOUBLE_EQ(r.matches[j].distance, want[j].distance);
      }
      ++described;
    }
  };
  for_each_keyframe(vo.poses, vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      check(recognizer.add_keyframe(k, p, n, k.id == reset_id));
                    });
  check(recognizer.finish());
  EXPECT_EQ(described, offline.signatures.size());
  EXPECT_EQ(recognizer.database().size(), described);
  ASSERT_TRUE(recognizer.database().pose(0).has_value());  // keyframe poses are kept
  if (lookahead > 0) {
    EXPECT_EQ(described, vo.poses.size());  // no INIT_FRAME gap
  }
}

INSTANTIATE_TEST_SUITE_P(ForwardOnlyTwoSidedAndLanes, RecognizerStreaming,
                         ::testing::Values(std::make_pair(0.0, 0.0), std::make_pair(20.0, 0.0),
                                           std::make_pair(20.0, 3.5)));

// A street driven east, then west in the other lane (builtin:reverse): two-sided scans in the
// camera frame with lane versions recognise the reverse drive online; the paper's forward-only
// scan mostly does not. Top-1 within 10 m of the true place, over the westward keyframes.
int reverse_top1(const sim::VoOutput& vo, const sim::Trajectory& route, RecognizerConfig config,
                 int& revisits) {
  config.k = 1;
  Recognizer recognizer(config);
  std::vector<KeyframeResult> all;
  for_each_keyframe(vo.poses, vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      for (KeyframeResult& r : recognizer.add_keyframe(k, p, n))
                        all.push_back(std::move(r));
                    });
  for (KeyframeResult& r : recognizer.finish()) all.push_back(std::move(r));
  int correct = 0;
  revisits = 0;
  for (const KeyframeResult& r : all) {
    const Eigen::Isometry3d& T = route.T_world_cam[static_cast<std::size_t>(r.keyframe)];
    if (T.translation().x() > 90 || T.linear()(0, 2) > -0.9) continue;  // the westward drive
    ++revisits;
    if (r.matches.empty()) continue;
    const auto& m = route.T_world_cam[static_cast<std::size_t>(r.matches[0].place.keyframe)];
    correct += (m.translation() - T.translation()).norm() < 10;
  }
  return correct;
}

TEST(Recognizer, RecognisesAStreetDrivenBothWays) {
  const sim::Trajectory route = sim::make_builtin_trajectory("reverse");
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::VoOutput vo = sim::simulate_vo(route, sim::select_keyframes(route), world,
                                            sim::Conditions::for_season(sim::Season::Summer),
                                            sim::StereoCamera{}, sim::VoSimConfig{});
  int revisits = 0;
  const int paper = reverse_top1(vo, route, RecognizerConfig::make(Method::ScanContext), revisits);
  RecognizerConfig lanes = RecognizerConfig::make(Method::ScanContext);
  lanes.imitation.lookahead_m = 20;
  lanes.descriptors.scan_context.frame = DescriptorFrame::Camera;
  lanes.lane_offset_m = 3.5;
  int revisits_lanes = 0;
  const int ours = reverse_top1(vo, route, lanes, revisits_lanes);
  ASSERT_GT(revisits_lanes, 30);
  EXPECT_GE(ours, 0.4 * revisits_lanes) << ours << " of " << revisits_lanes;
  EXPECT_GE(ours, 2 * paper) << "paper's scan: " << paper << " of " << revisits;
  std::printf("reverse drive, top-1 correct: lanes %d of %d, paper's scan %d of %d\n", ours,
              revisits_lanes, paper, revisits);
}

}  // namespace
}  // namespace loopscan
