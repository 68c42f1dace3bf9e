// The default-mode pipeline end to end on the built-in tiny scene (what `loopscan demo` runs).
#include <gtest/gtest.h>

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
    // The second lap revisits every place of the first: most must be recognised.
    EXPECT_GT(ev.pr.auc, 0.8) << method_name(method);
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

}  // namespace
}  // namespace loopscan
