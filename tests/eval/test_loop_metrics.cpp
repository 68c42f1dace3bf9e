// Trajectory metrics against evo's own results on ORB-SLAM2's KITTI 00 trajectory, and the
// loop truth on constructed poses.
#include <gtest/gtest.h>

#include <filesystem>

#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

std::vector<Eigen::Isometry3d> isometries(const std::vector<Eigen::Matrix<double, 3, 4>>& m) {
  std::vector<Eigen::Isometry3d> out;
  for (const auto& T : m) {
    Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    I.matrix().topRows<3>() = T;
    out.push_back(I);
  }
  return out;
}

TEST(LoopMetrics, ApeAndRpeMatchEvoOnOrbSlam2Kitti00) {
  const std::string orb = test::shared_dir() + "/data/real/evo-kitti00/KITTI_00_ORB.txt";
  const std::string gt_path = test::shared_dir() + "/data/kitti/poses/00.txt";
  LOOPSCAN_SKIP_WITHOUT_SHARED(std::filesystem::exists(orb) && std::filesystem::exists(gt_path),
                               orb << " and " << gt_path);
  const auto est = isometries(io::read_kitti_poses(orb));
  const auto gt = isometries(io::read_kitti_poses(gt_path));
  // evo_ape kitti KITTI_00_gt.txt KITTI_00_ORB.txt --align: rmse 1.3034 m (res_files).
  EXPECT_NEAR(eval::ate_rmse(gt, est), 1.3034, 5e-5);
  // evo_rpe ... --delta 10 --delta_unit m: rmse 0.2263 m.
  EXPECT_NEAR(eval::relative_pose_error(gt, est, 10.0).translation_rmse_m, 0.2263, 5e-5);
}

TEST(LoopMetrics, RpeCountsPairsAlongThePathAndSeesAConstantBias) {
  std::vector<Eigen::Isometry3d> gt, est;
  for (int i = 0; i < 101; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0, 0, 1.0 * i);
    gt.push_back(T);
    T.translation() *= 1.01;  // 1 % scale drift
    est.push_back(T);
  }
  const eval::RelativeError r = eval::relative_pose_error(gt, est, 10.0);
  EXPECT_EQ(r.pairs, 9);  // poses 10, 20, ..., 100 (estimated path of 10.1 m a pair)
  EXPECT_NEAR(r.translation_rmse_m, 0.1, 1e-9);  // 1 % of 10 m
  EXPECT_NEAR(r.rotation_rmse_deg, 0.0, 1e-9);
  EXPECT_THROW(eval::relative_pose_error(gt, est, 0.0), std::invalid_argument);
  est.pop_back();
  EXPECT_THROW(eval::relative_pose_error(gt, est, 10.0), std::invalid_argument);
}

TEST(LoopMetrics, LoopTruthComparesTheRelativePose) {
  Eigen::Isometry3d q = Eigen::Isometry3d::Identity(), m = Eigen::Isometry3d::Identity();
  q.translation() = Eigen::Vector3d(1, 0, 2);
  m.translation() = Eigen::Vector3d(4, 0, 6);
  m.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Isometry3d exact = q.inverse() * m;
  eval::LoopTruth t = eval::loop_truth(exact, q, m);
  EXPECT_NEAR(t.gt_distance_m, 5.0, 1e-12);
  EXPECT_TRUE(t.is_true);
  EXPECT_NEAR(t.translation_error_m, 0, 1e-12);
  Eigen::Isometry3d off = exact;
  off.translation().x() += 0.3;
  off.linear() = off.linear() * Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  t = eval::loop_truth(off, q, m, 4.0);
  EXPECT_FALSE(t.is_true);
  EXPECT_NEAR(t.translation_error_m, 0.3, 1e-9);
  EXPECT_NEAR(t.rotation_error_deg, 2.0, 1e-9);
}

}  // namespace
}  // namespace loopscan
