// The default-mode pipeline end to end on the built-in tiny scene (what `loopscan demo` runs).
#include <gtest/gtest.h>

#include <cstdio>
#include <thread>
#include <utility>
#include <vector>

#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/sim/tiny_scene.hpp"

namespace loopscan {
namespace {

TEST(Pipeline, TinySceneIsDeterministic) {
  const sim::TinyScene a = sim::make_tiny_scene(), b = sim::make_tiny_scene();
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); i += 97) {
    EXPECT_EQ(a.points[i].p_world, b.points[i].p_world);
  }
  sim::TinySceneConfig other;
  other.seed = 8;
  EXPECT_NE(sim::make_tiny_scene(other).points[5].p_world, a.points[5].p_world);
}

TEST(Pipeline, EveryMethodRecognisesRevisitsOfTheTinyScene) {
  sim::TinySceneConfig cfg;
  cfg.block_m = 80;  // smaller than the demo, to keep the test quick
  const sim::TinyScene scene = sim::make_tiny_scene(cfg);
  for (Method method : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    const SequenceSignatures sigs =
        describe_sequence(scene.poses, scene.points, SequenceOptions::make(method, Mode::Default));
    ASSERT_EQ(sigs.signatures.size(), scene.poses.size() - 30);
    std::vector<Eigen::Vector3d> pos;
    for (int id : sigs.keyframe_ids) pos.push_back(scene.positions[id]);
    eval::PlaceEvaluationOptions o;
    o.method = method;
    const eval::PlaceEvaluation ev =
        eval::evaluate_places(sigs.signatures, sigs.signatures, pos, pos, o);
    EXPECT_GT(ev.pr.n_gt_loops, 100);
    std::printf("%s: AUC %.4f, recall at 100 %% precision %.4f\n", method_name(method).c_str(),
                ev.pr.auc, ev.pr.recall_at_100_precision);
    // The second lap revisits every place of the first: most must be recognised (measured AUC
    // 0.971 Scan Context, 0.976 M2DP, 0.997 DELIGHT).
    EXPECT_GT(ev.pr.auc, 0.95) << method_name(method);
  }
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

TEST(Pipeline, ThreadsDoNotChangeSignatures) {
  sim::TinySceneConfig cfg;
  cfg.block_m = 60;
  const sim::TinyScene scene = sim::make_tiny_scene(cfg);
  for (Method method : {Method::ScanContext, Method::M2dp}) {
    SequenceOptions one = SequenceOptions::make(method, Mode::Default), two = one;
    two.threads = 2;
    const SequenceSignatures a = describe_sequence(scene.poses, scene.points, one);
    const SequenceSignatures b = describe_sequence(scene.poses, scene.points, two);
    ASSERT_EQ(a.keyframe_ids, b.keyframe_ids);
    ASSERT_EQ(a.signatures.size(), b.signatures.size());
    for (std::size_t i = 0; i < a.signatures.size(); ++i) {
      ASSERT_EQ(a.signatures[i], b.signatures[i]) << method_name(method) << " place " << i;
    }
  }
}

// Progress callbacks: on the calling thread only, counts rising to exactly (total, total) once,
// and the results equal to a run without them (two threads, adaptive fusion's two passes).
TEST(Pipeline, ProgressIsReportedOnTheCallersThreadAndChangesNothing) {
  sim::TinySceneConfig cfg;
  cfg.block_m = 60;
  const sim::TinyScene scene = sim::make_tiny_scene(cfg);
  const std::thread::id caller = std::this_thread::get_id();
  struct Log {
    std::vector<std::pair<std::size_t, std::size_t>> calls;
    bool off_thread = false;
  };
  const auto recorder = [caller](Log& log) {
    return [caller, &log](std::size_t done, std::size_t total) {
      log.off_thread = log.off_thread || std::this_thread::get_id() != caller;
      log.calls.emplace_back(done, total);
    };
  };
  const auto expect_well_formed = [](const Log& log, std::size_t total, const char* what) {
    ASSERT_FALSE(log.calls.empty()) << what;
    EXPECT_FALSE(log.off_thread) << what;
    std::size_t previous = 0, complete = 0;
    for (const auto& [done, all] : log.calls) {
      EXPECT_EQ(all, total) << what;
      EXPECT_GE(done, previous) << what;
      complete += done == all ? 1 : 0;
      previous = done;
    }
    EXPECT_EQ(complete, 1u) << what;  // 100 % once, at the very end
    EXPECT_EQ(log.calls.back().first, total) << what;
  };
  SequenceOptions options = SequenceOptions::make(Method::ScanContext, Mode::Default);
  options.threads = 2;
  const SequenceSignatures quiet = describe_sequence(scene.poses, scene.points, options);
  Log describing;
  options.progress = recorder(describing);
  const SequenceSignatures reported = describe_sequence(scene.poses, scene.points, options);
  expect_well_formed(describing, scene.poses.size(), "describe_sequence");
  ASSERT_EQ(reported.signatures.size(), quiet.signatures.size());
  for (std::size_t i = 0; i < quiet.signatures.size(); ++i)
    EXPECT_EQ(reported.signatures[i], quiet.signatures[i]) << i;

  std::vector<Eigen::Vector3d> pos;
  for (int id : quiet.keyframe_ids) pos.push_back(scene.positions[id]);
  eval::PlaceEvaluationOptions o;
  o.fusion = Fusion::Adaptive;
  o.threads = 2;
  const eval::PlaceEvaluation a =
      eval::evaluate_places(quiet.signatures, quiet.signatures, pos, pos, o);
  Log matching;
  o.progress = recorder(matching);
  const eval::PlaceEvaluation b =
      eval::evaluate_places(quiet.signatures, quiet.signatures, pos, pos, o);
  expect_well_formed(matching, 2 * quiet.signatures.size(), "evaluate_places");
  ASSERT_EQ(a.matches.size(), b.matches.size());
  for (std::size_t i = 0; i < a.matches.size(); ++i) {
    EXPECT_EQ(a.matches[i].match, b.matches[i].match) << i;
    EXPECT_EQ(a.matches[i].distance, b.matches[i].distance) << i;
  }
}

}  // namespace
}  // namespace loopscan
