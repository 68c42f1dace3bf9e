// The online loop closer on simulated drives with a drifting VO: true loops only, a trajectory
// pulled back towards the ground truth, recognition identical to the Recognizer's, a second
// session placed in a saved map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "closure/drives.hpp"
#include "loopscan/config/config_file.hpp"

namespace loopscan {
namespace {

using test::centres;
using test::close_drive;
using test::Closed;
using test::Drive;
using test::drive;
using test::drive_in;
using test::stream;

const Drive& summer() {
  static const Drive d = drive(sim::Season::Summer, 1);
  return d;
}

TEST(LoopCloser, ClosesADriftedBlockWithTrueLoopsOnly) {
  const Drive& d = summer();
  closure::LoopCloser closer(closure::LoopCloserConfig::make(Method::ScanContext));
  stream(d, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    closer.add_keyframe(k, p, n);
  });
  closer.finish();
  const std::vector<Eigen::Vector3d> gt = test::truth(d);
  const double before = eval::aligned_rmse(gt, centres(d.vo.poses));
  const double after = eval::aligned_rmse(gt, centres(closer.corrected_poses()));
  int accepted = 0;
  for (const closure::Loop& l : closer.loops()) {
    if (!l.accepted()) continue;
    ++accepted;
    const eval::LoopTruth t =
        eval::loop_truth(l.T_query_match, d.route.T_world_cam[std::size_t(l.query)],
                         d.route.T_world_cam[std::size_t(l.match.keyframe)]);
    EXPECT_TRUE(t.is_true) << l.query << " -> " << l.match.keyframe << ": " << t.gt_distance_m
                           << " m";
    EXPECT_LT(t.translation_error_m, 0.6);
    EXPECT_LT(t.rotation_error_deg, 2.0);
  }
  EXPECT_GE(accepted, 3);
  EXPECT_GT(before, 0.4);  // the drift is real
  EXPECT_LT(after, before / 2) << before << " -> " << after;
  const closure::StageTimes& times = closer.times();
  EXPECT_EQ(times.keyframes, int(d.vo.poses.size()));
  // Keyframes at a place the map held linked to it; every other described one joined.
  EXPECT_GT(times.linked, 0);
  EXPECT_EQ(closer.database().size(), std::size_t(times.described - times.linked));
  EXPECT_EQ(closer.place_clouds().size(), closer.database().size());
}

// The reverse route drives half a street again the other way round, one lane over: the
// descriptor does not find those places, the trajectory estimate does, and verification
// aligns them from the pose it predicts.
TEST(LoopCloser, ClosesReverseRevisits) {
  const Drive d = drive(sim::Season::Summer, 1, "reverse");
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  const Closed c = close_drive(d, config);
  EXPECT_EQ(c.false_loops, 0) << c.false_list;
  ASSERT_GT(c.revisits, 30);
  // (Issue 28 asks for 60 %; the ambiguity test refuses the alignments that slide along the
  // street, which opposite headings often do: 39 % today, docs/loop-closing.md.)
  EXPECT_GE(c.closed, 0.3 * c.revisits) << c.closed << " of " << c.revisits;
  EXPECT_LT(c.ate_after, c.ate_before) << c.ate_before << " -> " << c.ate_after;
  // With the nearby places' alignments started from the bird's-eye search, more close than
  // from starts along the track (27 against 22 of 56), none false.
  closure::LoopCloserConfig birds_eye = config;
  birds_eye.verify.birds_eye.enabled = true;
  const Closed b = close_drive(d, birds_eye);
  EXPECT_EQ(b.false_loops, 0) << b.false_list;
  EXPECT_GT(b.closed, c.closed);
  config.proximity.candidates = 0;  // the descriptor alone
  EXPECT_LT(close_drive(d, config).closed, c.closed / 2);
  // Each loop's covariance is calibrated: its translation error, whitened by it, is of the
  // order of one (neither hidden in a loose covariance nor far outside a tight one).
  std::vector<double> w = c.whitened;
  ASSERT_FALSE(w.empty());
  std::sort(w.begin(), w.end());
  EXPECT_GT(w[w.size() / 2], 0.1);
  EXPECT_LT(w[w.size() / 2], 1.5);
  EXPECT_LT(w[w.size() * 9 / 10], 3.5);
}

// A VO with little drift: loops may not make the trajectory worse. (On the reverse route the
// opposite-heading loops' along-track error still does: 0.23 -> 0.32 m, docs/loop-closing.md.)
TEST(LoopCloser, NeverWorseOnANearlyDriftFreeDrive) {
  for (const std::string route : {"short"}) {
    const Drive d = drive(sim::Season::Summer, 2, route, 0.002);
    const Closed c = close_drive(d, closure::LoopCloserConfig::make(Method::ScanContext));
    EXPECT_EQ(c.false_loops, 0) << route << ": " << c.false_list;
    EXPECT_GT(c.closed, 0) << route;
    EXPECT_LE(c.ate_after, c.ate_before) << route;
  }
}

// Worlds of other statistics than the default street, the study's (docs/experiments/worlds:
// each file's world and drifting VO): bare facades, where alignments slide along the street; low buildings broken by gaps, trees
// and parked cars; tall facades set close to the street. Verification holds in each: true
// loops only, a share of the revisits closed (9-13 of 43 now) and the drift more than halved.
TEST(LoopCloser, WorldsOfOtherStatisticsCloseTrueLoopsOnly) {
  for (const char* name : {"bare-facades", "low-and-broken", "tall-and-close"}) {
    const std::string path =
        std::string(LOOPSCAN_SOURCE_DIR) + "/docs/experiments/worlds/" + name + ".yaml";
    const SimulatorSettings settings = load_configuration(path, "sc", Mode::Default).simulator;
    const Drive d = drive_in(sim::Season::Summer, 1, "short", 1, settings.world, settings.vo);
    const Closed c = close_drive(d, closure::LoopCloserConfig::make(Method::ScanContext));
    EXPECT_EQ(c.false_loops, 0) << name << ": " << c.false_list;
    EXPECT_GE(c.closed, c.revisits / 8) << name << ": " << c.closed << " of " << c.revisits;
    EXPECT_LT(c.ate_after, c.ate_before / 2)
        << name << ": " << c.ate_before << " -> " << c.ate_after;
  }
}

// The VO restarts in a new frame some 40 keyframes before the block's first street is driven
// again. The scan builds up again for 30 of them, which the query's band of recent places
// counts (every keyframe given, described or not), so the places before the reset are
// searchable by the revisit, which ties the two runs into one frame: no false loop, and both
// halves of the drive corrected together.
TEST(LoopCloser, AVoResetBeforeTheRevisitTiesBothRunsAtIt) {
  const Drive& d = summer();
  const std::vector<Eigen::Vector3d> gt = test::truth(d);
  std::size_t first_revisit = 0;
  while (first_revisit < gt.size() && !test::is_revisit(gt, first_revisit)) ++first_revisit;
  ASSERT_GT(first_revisit, 100u);
  const std::size_t at = first_revisit - 40;
  const Drive reset = test::with_vo_reset(d, at);
  const closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  const Closed c = close_drive(reset, config, reset.vo.poses[at].id);
  const Closed plain = close_drive(d, config);
  EXPECT_EQ(c.false_loops, 0) << c.false_list;
  EXPECT_GT(c.ate_before, 10.0);  // the two runs in unrelated frames
  EXPECT_LT(c.ate_after, 2.0) << c.ate_before << " -> " << c.ate_after;
  EXPECT_GE(c.closed, plain.closed / 2)
      << c.closed << " of " << c.revisits << " (without the reset " << plain.closed << ")";
}

// The same block driven three times: the later laps link to the places the earlier ones left
// instead of copying them (their graph nodes merge into the places'), and close as many
// revisits, as accurately, as a map and graph of every copy would.
TEST(LoopCloser, LapsLinkToTheMapInsteadOfGrowingIt) {
  const Drive three = drive(sim::Season::Summer, 1, "short", 0.02, 3);
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  config.lifelong.merge_after_keyframes = 50;  // (laps of about 180 keyframes)
  const Closed lifelong = close_drive(three, config);
  config.lifelong.enabled = false;
  const Closed copies = close_drive(three, config);
  EXPECT_EQ(lifelong.false_loops, 0) << lifelong.false_list;
  EXPECT_EQ(copies.false_loops, 0) << copies.false_list;
  // The third lap (from the start of its route) drives only where the map has been: 174
  // keyframes, 7 of which joined the map (every one without linking).
  const int third_lap_start =
      static_cast<int>(three.route.T_world_cam.size()) -
      static_cast<int>(sim::make_builtin_trajectory("short").T_world_cam.size());
  auto joined_in_third_lap = [&](const Closed& c) {
    return std::count_if(c.joined.begin(), c.joined.end(),
                         [&](int id) { return id >= third_lap_start; });
  };
  int third_lap_keyframes = 0;
  for (const KeyframePose& k : three.vo.poses) third_lap_keyframes += k.id >= third_lap_start;
  EXPECT_GT(joined_in_third_lap(copies), 0.9 * third_lap_keyframes);
  EXPECT_LT(joined_in_third_lap(lifelong), 0.25 * third_lap_keyframes);
  EXPECT_LT(lifelong.map_places, 0.6 * copies.map_places);
  // Linked keyframes' nodes merged into their places' (but the last 50 keyframes'): the pose
  // graph shrinks with the map.
  EXPECT_EQ(copies.graph_nodes, three.vo.poses.size());
  EXPECT_LT(lifelong.graph_nodes, 0.6 * copies.graph_nodes);
  EXPECT_LT(lifelong.graph_edges, 0.6 * copies.graph_edges);
  EXPECT_GE(lifelong.closed, 0.95 * copies.closed)
      << lifelong.closed << " of " << lifelong.revisits;
  EXPECT_LE(lifelong.ate_after, 1.1 * copies.ate_after + 0.05)
      << copies.ate_after << " with every copy";
}

TEST(LoopCloser, RecognitionIsTheRecognizersAndRunsAreRepeatable) {
  const Drive& d = summer();
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  config.lifelong.enabled = false;  // the Recognizer keeps every place
  closure::LoopCloser a(config), b(config);
  RecognizerConfig rc = config.recognition;
  rc.k = config.candidates;
  Recognizer recognizer(rc);
  stream(d, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    const closure::KeyframeClosure ra = a.add_keyframe(k, p, n);
    const closure::KeyframeClosure rb = b.add_keyframe(k, p, n);
    const std::vector<KeyframeResult> rs = recognizer.add_keyframe(k, p, n);
    ASSERT_EQ(ra.described, !rs.empty());
    if (rs.empty()) return;
    const KeyframeResult& r = rs.front();
    ASSERT_EQ(ra.candidates.size(), r.matches.size());
    for (std::size_t i = 0; i < r.matches.size(); ++i) {
      EXPECT_TRUE(ra.candidates[i].place == r.matches[i].place);
      EXPECT_EQ(ra.candidates[i].distance, r.matches[i].distance);
    }
    ASSERT_EQ(ra.verified.size(), rb.verified.size());
    for (std::size_t i = 0; i < ra.verified.size(); ++i) {
      EXPECT_EQ(ra.verified[i].verdict, rb.verified[i].verdict);
      EXPECT_EQ(ra.verified[i].T_query_match.matrix(), rb.verified[i].T_query_match.matrix());
    }
  });
  a.finish();
  b.finish();
  EXPECT_TRUE(test::same_poses(a.corrected_poses(), b.corrected_poses()));
}

// A place is classified when a verification first needs it (or when too many wait); the oracle
// classifies every place as it joins the map. Loops, poses and clouds must not tell them apart.
TEST(LoopCloser, PlacesClassifiedOnFirstUseAreThoseClassifiedAtOnce) {
  const Drive& d = summer();
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  closure::LoopCloserConfig at_once = config, few = config;
  at_once.cloud.max_unclassified_places = 0;
  few.cloud.max_unclassified_places = 3;
  closure::LoopCloser lazy(config), oracle(at_once), capped(few);
  std::size_t most_waiting = 0;
  stream(d, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    lazy.add_keyframe(k, p, n);
    oracle.add_keyframe(k, p, n);
    capped.add_keyframe(k, p, n);
    EXPECT_EQ(oracle.unclassified_places(), 0u);
    EXPECT_LE(capped.unclassified_places(), 3u);
    most_waiting = std::max(most_waiting, capped.unclassified_places());
  });
  lazy.finish();
  oracle.finish();
  capped.finish();
  // Most places were never a candidate: they still wait (the property is not vacuous).
  EXPECT_GT(lazy.unclassified_places(), lazy.database().size() / 2);
  EXPECT_EQ(most_waiting, 3u);
  for (const closure::LoopCloser* c : {&lazy, &capped}) {
    EXPECT_TRUE(test::same_loops(c->loops(), oracle.loops()));
    EXPECT_TRUE(test::same_poses(c->corrected_poses(), oracle.corrected_poses()));
    EXPECT_TRUE(test::same_clouds(c->place_clouds(), oracle.place_clouds()));
    EXPECT_EQ(c->unclassified_places(), 0u);  // place_clouds classified the rest
  }
}

// Alignments and plane fits on several threads: the same verifications, poses and clouds.
TEST(LoopCloser, ThreadsGiveTheSameLoopsPosesAndClouds) {
  const Drive& d = summer();
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  closure::LoopCloserConfig threaded = config;
  threaded.threads = 3;
  closure::LoopCloser one(config), three(threaded);
  stream(d, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    one.add_keyframe(k, p, n);
    three.add_keyframe(k, p, n);
  });
  one.finish();
  three.finish();
  ASSERT_GT(std::count_if(one.loops().begin(), one.loops().end(),
                          [](const closure::Loop& l) { return l.verdict == closure::Verdict::Accepted; }),
            3);
  EXPECT_TRUE(test::same_loops(three.loops(), one.loops()));
  EXPECT_TRUE(test::same_poses(three.corrected_poses(), one.corrected_poses()));
  EXPECT_GT(three.unclassified_places(), 3u);  // the map's waiting places, on threads too
  EXPECT_TRUE(test::same_clouds(three.place_clouds(), one.place_clouds()));
  closure::LoopCloserConfig none = config;
  none.threads = 0;
  EXPECT_THROW(closure::LoopCloser{none}, std::invalid_argument);
}

TEST(LoopCloser, ASecondSessionJoinsTheSavedMapAtItsFirstLoop) {
  const Drive& map_drive = summer();
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  closure::LoopCloser first(config);
  stream(map_drive, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    first.add_keyframe(k, p, n);
  });
  first.finish();
  const std::vector<KeyframePose> map_poses = first.corrected_poses();

  const Drive winter = drive(sim::Season::Winter, 9);
  config.recognition.session = 1;
  closure::LoopCloser second(config, first.corrected_map(), first.place_clouds());
  EXPECT_FALSE(second.anchored());
  stream(winter, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    second.add_keyframe(k, p, n);
  });
  second.finish();
  ASSERT_TRUE(second.anchored());
  EXPECT_LT(second.anchored_at(), 80);  // early in a 174-keyframe drive
  // In one frame: every accepted cross-session loop joins two keyframes that are as far apart
  // in the map frame as the ground truth says.
  const std::vector<KeyframePose> poses = second.corrected_poses();
  std::unordered_map<int, Eigen::Vector3d> mine, theirs;
  for (std::size_t i = 0; i < poses.size(); ++i) mine[poses[i].id] = centres({poses[i]})[0];
  for (std::size_t i = 0; i < map_poses.size(); ++i)
    theirs[map_poses[i].id] = centres({map_poses[i]})[0];
  int cross = 0;
  for (const closure::Loop& l : second.loops()) {
    if (!l.accepted() || l.match.session != 0) continue;
    ++cross;
    const double gt = (winter.route.T_world_cam[std::size_t(l.query)].translation() -
                       map_drive.route.T_world_cam[std::size_t(l.match.keyframe)].translation())
                          .norm();
    EXPECT_LT(gt, 10.0);
    EXPECT_NEAR((mine[l.query] - theirs[l.match.keyframe]).norm(), gt, 1.0) << l.query;
  }
  EXPECT_GE(cross, 20);
  // A map without clouds, of another method, or holding this session already is refused.
  EXPECT_THROW(closure::LoopCloser(config, first.corrected_map(), {}), std::invalid_argument);
  closure::LoopCloserConfig m2dp = closure::LoopCloserConfig::make(Method::M2dp);
  m2dp.recognition.session = 1;
  EXPECT_THROW(closure::LoopCloser(m2dp, first.corrected_map(), first.place_clouds()),
               std::invalid_argument);
  config.recognition.session = 0;
  EXPECT_THROW(closure::LoopCloser(config, first.corrected_map(), first.place_clouds()),
               std::invalid_argument);
  // The map records how its places were described: another mode or frame is refused, named.
  EXPECT_EQ(first.corrected_map().config().mode, Mode::Default);
  // The closer describes as `describe` does (one recognition path): the camera frame.
  EXPECT_EQ(first.corrected_map().config().frame, DescriptorFrame::Camera);
  closure::LoopCloserConfig pca = closure::LoopCloserConfig::make(Method::ScanContext);
  pca.recognition.session = 1;
  pca.recognition.descriptors.scan_context.frame = DescriptorFrame::Pca;
  try {
    closure::LoopCloser closer(pca, first.corrected_map(), first.place_clouds());
    ADD_FAILURE() << "a PCA-frame closer took a camera-frame map";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("the map's places were described in the camera frame, "
                                         "this describes in the pca frame"),
              std::string::npos)
        << e.what();
  }
  closure::LoopCloserConfig reference =
      closure::LoopCloserConfig::make(Method::ScanContext, Mode::Reference);
  reference.recognition.session = 1;
  EXPECT_THROW(closure::LoopCloser(reference, first.corrected_map(), first.place_clouds()),
               std::invalid_argument);
}

// Stages every keyframe runs are averaged over keyframes, those of described keyframes over
// described ones, verification also over verified candidates, the graph over solves; an empty
// count gives 0, not a division by zero.
TEST(StageMeans, EachStageOverTheKeyframesThatRanIt) {
  closure::StageTimes t;
  t.scan = 40, t.describe = 12, t.cloud = 30, t.query = 6, t.verify = 90, t.graph = 20;
  t.keyframes = 10, t.described = 6, t.verifications = 9, t.solves = 4;
  const closure::StageMeans m = closure::stage_means(t);
  EXPECT_DOUBLE_EQ(m.scan, 4.0);
  EXPECT_DOUBLE_EQ(m.describe, 2.0);
  EXPECT_DOUBLE_EQ(m.cloud, 5.0);
  EXPECT_DOUBLE_EQ(m.query, 1.0);
  EXPECT_DOUBLE_EQ(m.verify, 15.0);
  EXPECT_DOUBLE_EQ(m.graph, 2.0);
  EXPECT_DOUBLE_EQ(m.per_verification, 10.0);
  EXPECT_DOUBLE_EQ(m.per_solve, 5.0);
  t.keyframes = t.described = t.verifications = t.solves = 0;
  const closure::StageMeans none = closure::stage_means(t);
  for (double v : {none.scan, none.describe, none.cloud, none.query, none.verify, none.graph,
                   none.per_verification, none.per_solve}) {
    EXPECT_EQ(v, 0.0);
  }
}

TEST(LoopCloser, BadKeyframesAreRefused) {
  closure::LoopCloser closer(closure::LoopCloserConfig::make(Method::ScanContext));
  KeyframePose k;
  k.id = 4;
  closer.add_keyframe(k, nullptr, 0);
  EXPECT_THROW(closer.add_keyframe(k, nullptr, 0), std::invalid_argument);  // the same id again
  k.id = 5;
  k.T_cam_world(0, 3) = std::nan("");
  EXPECT_THROW(closer.add_keyframe(k, nullptr, 0), std::invalid_argument);
  closure::LoopCloserConfig bad = closure::LoopCloserConfig::make(Method::ScanContext);
  bad.consistency.required = 0;
  EXPECT_THROW(closure::LoopCloser{bad}, std::invalid_argument);
  bad = closure::LoopCloserConfig::make(Method::ScanContext);
  bad.proximity.min_overlap = 1.5;
  EXPECT_THROW(closure::LoopCloser{bad}, std::invalid_argument);
  bad = closure::LoopCloserConfig::make(Method::ScanContext);
  bad.proximity.base_radius_m = -1;
  EXPECT_THROW(closure::LoopCloser{bad}, std::invalid_argument);
  bad = closure::LoopCloserConfig::make(Method::ScanContext);
  bad.lifelong.max_distance_m = std::nan("");
  EXPECT_THROW(closure::LoopCloser{bad}, std::invalid_argument);
  bad = closure::LoopCloserConfig::make(Method::ScanContext);
  bad.lifelong.max_rotation_deg = 200;
  EXPECT_THROW(closure::LoopCloser{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
