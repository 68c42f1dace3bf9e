// Reference mode against the authors' outputs on the k06-summer fixture: identical keyframe
// ids, signatures within 1e-6 relative, AUC / max recall within 1e-4 of their metrics.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "loopscan/core/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/sodso.hpp"
#include "test_support.hpp"

namespace loopscan {
namespace {

struct Fixture {
  std::vector<KeyframePose> poses;
  std::vector<IdPoint> points;
  std::vector<Eigen::Vector3d> gt;
  std::vector<int> ids;
  nlohmann::json metrics;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    const std::string d = test::fixture_dir();
    Fixture x{io::read_sodso_poses(d + "/poses_history_file.txt"),
              io::read_sodso_points(d + "/pts_history_file.txt.gz"),
              io::read_positions(d + "/gt.txt", io::GtFormat::Kitti),
              io::read_incoming_ids(d + "/reference/incoming_id_file.txt"), {}};
    std::ifstream(d + "/reference/metrics.json") >> x.metrics;
    return x;
  }();
  return f;
}

// Reference-mode signatures of the whole fixture; M2DP's SVDs run on two threads.
SequenceSignatures describe_fixture(Method method) {
  const Fixture& f = fixture();
  SequenceOptions options = SequenceOptions::make(method, Mode::Reference);
  if (method != Method::M2dp) return describe_sequence(f.poses, f.points, options);
  // Imitate sequentially (it is stateful), describe in parallel.
  SequenceSignatures out;
  ScanImitator imitator(options.imitation);
  std::vector<Cloud> scans;
  Cloud in_range;
  std::size_t next = 0;
  for (const KeyframePose& k : f.poses) {
    const std::size_t first = next;
    while (next < f.points.size() && f.points[next].id <= k.id) ++next;
    if (imitator.add_keyframe(k, f.points.data() + first, next - first, false, in_range)) {
      scans.push_back(filter_scan(in_range, ScanFilter::Polar, options.imitation));
      out.keyframe_ids.push_back(k.id);
    }
  }
  out.signatures.resize(scans.size());
  auto work = [&](std::size_t begin) {
    for (std::size_t i = begin; i < scans.size(); i += 2) {
      out.signatures[i] = describe(method, scans[i], options.descriptors);
    }
  };
  std::thread t(work, 1);
  work(0);
  t.join();
  return out;
}

void expect_signatures_match(Method method, const SequenceSignatures& ours) {
  const Fixture& f = fixture();
  ASSERT_EQ(ours.keyframe_ids, f.ids);
  const Eigen::MatrixXd ref = io::read_matrix_text(test::fixture_dir() +
                                                   "/reference/signatures_" +
                                                   method_name(method) + ".txt.gz");
  const int rows = rows_per_place(method);
  ASSERT_EQ(ref.rows(), static_cast<Eigen::Index>(ours.signatures.size()) * rows);
  int bad = 0;
  for (std::size_t i = 0; i < ours.signatures.size(); ++i) {
    for (int r = 0; r < rows; ++r) {
      const Eigen::RowVectorXd theirs = ref.row(static_cast<Eigen::Index>(i) * rows + r);
      const Eigen::RowVectorXd mine = ours.signatures[i].row(r);
      const double scale = std::max(theirs.cwiseAbs().maxCoeff(), 1e-12);
      const double err = (mine - theirs).cwiseAbs().maxCoeff() / scale;
      if (err > 1e-6 && ++bad <= 3) ADD_FAILURE() << "place " << i << " row " << r << ": " << err;
    }
  }
  EXPECT_EQ(bad, 0);
}

void expect_metrics_match(Method method, const std::vector<Signature>& sigs, Fusion fusion) {
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
  EXPECT_NEAR(ev.pr.auc, m["auc"].get<double>(), 1e-4) << method_name(method) << " " << fusion_name(fusion);
  EXPECT_NEAR(ev.pr.recall_at_100_precision, m["recall_at_100_precision"].get<double>(), 1e-4);
  EXPECT_EQ(ev.pr.n_gt_loops, m["n_gt_loops"].get<int>());
}

TEST(Conformance, ScanContextReferenceMode) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const SequenceSignatures ours = describe_fixture(Method::ScanContext);
  expect_signatures_match(Method::ScanContext, ours);
  for (Fusion fu : {Fusion::Fused, Fusion::Structure, Fusion::Intensity}) {
    expect_metrics_match(Method::ScanContext, ours.signatures, fu);
  }
}

TEST(Conformance, DelightReferenceMode) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const SequenceSignatures ours = describe_fixture(Method::Delight);
  expect_signatures_match(Method::Delight, ours);
  expect_metrics_match(Method::Delight, ours.signatures, Fusion::Fused);
}

TEST(Conformance, M2dpReferenceMode) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const SequenceSignatures ours = describe_fixture(Method::M2dp);
  expect_signatures_match(Method::M2dp, ours);  // the SVD signs match too (same Eigen routine)
  for (Fusion fu : {Fusion::Fused, Fusion::Structure, Fusion::Intensity}) {
    expect_metrics_match(Method::M2dp, ours.signatures, fu);
  }
}

}  // namespace
}  // namespace loopscan
