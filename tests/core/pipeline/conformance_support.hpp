#pragma once
// The k06-summer fixture and the authors' reference outputs, shared by the conformance tests
// (the default suite's and the long suite's).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/sodso.hpp"
#include "support/test_support.hpp"

namespace loopscan::conformance {

struct Fixture {
  std::vector<KeyframePose> poses;
  std::vector<IdPoint> points;
  std::vector<Eigen::Vector3d> gt;
  std::vector<int> ids;
  nlohmann::json metrics;
};

inline const Fixture& fixture() {
  static const Fixture f = [] {
    const std::string d = test::fixture_dir();
    Fixture x{io::read_sodso_poses(d + "/poses_history_file.txt"),
              io::read_sodso_points(d + "/pts_history_file.txt.gz"),
              io::read_positions(d + "/gt.txt", io::GtFormat::Kitti),
              io::read_incoming_ids(d + "/reference/incoming_id_file.txt"),
              {}};
    std::ifstream(d + "/reference/metrics.json") >> x.metrics;
    return x;
  }();
  return f;
}

// Reference-mode signatures of the whole fixture (two threads: M2DP's Jacobi SVDs are slow).
inline SequenceSignatures describe_fixture(Method method) {
  const Fixture& f = fixture();
  SequenceOptions options = SequenceOptions::make(method, Mode::Reference);
  options.threads = 2;
  return describe_sequence(f.poses, f.points, options);
}

// The authors' signatures of one method (rows_per_place rows a place, in keyframe order).
inline Eigen::MatrixXd reference_signatures(Method method) {
  return io::read_matrix_text(test::fixture_dir() + "/reference/signatures_" + method_name(method) +
                              ".txt.gz");
}

// Largest relative difference of place i's rows from the authors' (relative to their row's
// largest magnitude).
inline double place_error(const Eigen::MatrixXd& ref, std::size_t i, const Signature& mine) {
  double worst = 0;
  for (Eigen::Index r = 0; r < mine.rows(); ++r) {
    const Eigen::RowVectorXd theirs = ref.row(static_cast<Eigen::Index>(i) * mine.rows() + r);
    const double scale = std::max(theirs.cwiseAbs().maxCoeff(), 1e-12);
    worst = std::max(worst, (mine.row(r) - theirs).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

inline void expect_signatures_match(Method method, const SequenceSignatures& ours) {
  const Fixture& f = fixture();
  ASSERT_EQ(ours.keyframe_ids, f.ids);
  const Eigen::MatrixXd ref = reference_signatures(method);
  ASSERT_EQ(ref.rows(), static_cast<Eigen::Index>(ours.signatures.size()) * rows_per_place(method));
  int bad = 0;
  for (std::size_t i = 0; i < ours.signatures.size(); ++i) {
    const double err = place_error(ref, i, ours.signatures[i]);
    if (err > 1e-6 && ++bad <= 3) ADD_FAILURE() << "place " << i << ": " << err;
  }
  EXPECT_EQ(bad, 0);
}

inline void expect_metrics_match(Method method, const std::vector<Signature>& sigs, Fusion fusion) {
  const Fixture& f = fixture();
  std::vector<Eigen::Vector3d> pos;
  for (int id : f.ids) pos.push_back(f.gt[id]);
  eval::PlaceEvaluationOptions o;
  o.method = method;
  o.fusion = fusion;
  o.precision = Precision::Double;
  o.reference_quirks = true;
  const eval::PlaceEvaluation ev = eval::evaluate_places(sigs, sigs, pos, pos, o);
  const auto& m = f.metrics[method_name(method)][fusion_name(fusion)];
  EXPECT_NEAR(ev.pr.auc, m["auc"].get<double>(), 1e-4)
      << method_name(method) << " " << fusion_name(fusion);
  EXPECT_NEAR(ev.pr.recall_at_100_precision, m["recall_at_100_precision"].get<double>(), 1e-4);
  EXPECT_EQ(ev.pr.n_gt_loops, m["n_gt_loops"].get<int>());
}

}  // namespace loopscan::conformance
