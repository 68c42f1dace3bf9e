// KITTI-style odometry metrics against trajectories whose errors are known by construction, and
// the segment search against a brute-force walk.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "loopscan/eval/odometry_metrics.hpp"

namespace loopscan {
namespace {

// A drive along z with a gentle curve, 1 m per frame.
std::vector<Eigen::Isometry3d> curvy_drive(int n) {
  std::vector<Eigen::Isometry3d> T;
  double yaw = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = p;
    T.push_back(pose);
    yaw += 0.01 * std::sin(i * 0.02);
    p += pose.linear() * Eigen::Vector3d(0, 0, 1.0);
  }
  return T;
}

TEST(OdometryMetrics, PerfectEstimateHasNoError) {
  const auto gt = curvy_drive(900);
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, gt);
  EXPECT_GT(m.segments, 0);
  EXPECT_NEAR(m.translation_percent, 0.0, 1e-9);
  EXPECT_NEAR(m.rotation_deg_per_100m, 0.0, 1e-5);
  EXPECT_NEAR(m.ate_rmse_m, 0.0, 1e-9);
  EXPECT_NEAR(m.path_length_m, 899.0, 1e-9);
  EXPECT_EQ(m.lengths_m.size(), 8u);
}

TEST(OdometryMetrics, ScaleDriftIsThePercentage) {
  // Every translation 1% too long on a straight line: every segment is 1% off.
  std::vector<Eigen::Isometry3d> gt, est;
  for (int i = 0; i < 500; ++i) {
    Eigen::Isometry3d a = Eigen::Isometry3d::Identity();
    a.translation() = Eigen::Vector3d(0, 0, i);
    gt.push_back(a);
    a.translation() *= 1.01;
    est.push_back(a);
  }
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, est);
  // Segments end at the first frame beyond the length: length + 1 m travelled.
  double expected = 0;
  for (const eval::SegmentError& e : eval::segment_errors(gt, est))
    expected += 100.0 * 0.01 * (e.last - e.first) / e.length_m;
  expected /= m.segments;
  EXPECT_NEAR(m.translation_percent, expected, 1e-9);
  EXPECT_NEAR(m.translation_percent, 1.0, 0.02);
  EXPECT_NEAR(m.rotation_deg_per_100m, 0.0, 1e-6);
  EXPECT_NEAR(m.end_point_error_percent, 1.0, 1e-9);
}

TEST(OdometryMetrics, RigidlyMovedEstimateHasNoRelativeErrorAndZeroAte) {
  const auto gt = curvy_drive(400);
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.linear() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  offset.translation() = Eigen::Vector3d(5, -3, 40);
  std::vector<Eigen::Isometry3d> est;
  for (const auto& T : gt) est.push_back(offset * T);
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, est);
  EXPECT_NEAR(m.translation_percent, 0.0, 1e-9);
  EXPECT_NEAR(m.ate_rmse_m, 0.0, 1e-8);
}

TEST(OdometryMetrics, TheSim3ScaleUndoesAnEstimateTooLong) {
  // 10 % too long and rigidly moved: the scale that takes it back is 1 / 1.1, the ATE after it
  // zero, the rigid ATE not.
  const auto gt = curvy_drive(400);
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 0)).toRotationMatrix();
  offset.translation() = Eigen::Vector3d(-7, 1, 12);
  std::vector<Eigen::Isometry3d> est;
  for (const auto& T : gt) {
    Eigen::Isometry3d e = T;
    e.translation() *= 1.1;
    est.push_back(offset * e);
  }
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, est);
  EXPECT_NEAR(m.sim3_scale, 1 / 1.1, 1e-9);
  EXPECT_NEAR(m.ate_sim3_rmse_m, 0.0, 1e-7);
  EXPECT_GT(m.ate_rmse_m, 5.0);
}

TEST(OdometryMetrics, TheSim3AlignmentIsTheBestScaleOfTheRigidOne) {
  // Oracle: the rigid ATE of the estimate scaled by s, minimised over s by a fine search; the
  // similarity alignment must find that s and that RMSE.
  const auto gt = curvy_drive(300);
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.4);
  std::vector<Eigen::Isometry3d> est;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    Eigen::Isometry3d e = gt[i];
    e.translation() = 0.93 * e.translation() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) +
                      Eigen::Vector3d(0, 0.002 * double(i), 0);
    est.push_back(e);
  }
  const auto scaled_ate = [&](double scale) {
    std::vector<Eigen::Isometry3d> s = est;
    for (auto& T : s) T.translation() *= scale;
    return eval::ate_rmse(gt, s);
  };
  double lo = 0.5, hi = 2.0;  // the rigid ATE of a scaled estimate is unimodal in the scale
  for (int it = 0; it < 200; ++it) {
    const double a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
    if (scaled_ate(a) < scaled_ate(b)) {
      hi = b;
    } else {
      lo = a;
    }
  }
  const double best = 0.5 * (lo + hi);
  const eval::Sim3Alignment sim3 = eval::sim3_alignment(gt, est);
  EXPECT_NEAR(sim3.scale, best, 1e-6);
  EXPECT_NEAR(sim3.rmse_m, scaled_ate(best), 1e-9);
  EXPECT_LT(sim3.rmse_m, eval::ate_rmse(gt, est));
}

TEST(OdometryMetrics, HeadingDriftShowsAsRotationError) {
  // The estimate turns an extra 0.02 rad every metre: the rotation error is 2 rad per 100 m
  // whatever the segment.
  const auto gt = curvy_drive(300);
  std::vector<Eigen::Isometry3d> est;
  for (std::size_t i = 0; i < gt.size(); ++i) {
    Eigen::Isometry3d T = gt[i];
    T.linear() =
        T.linear() * Eigen::AngleAxisd(0.0002 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    est.push_back(T);
  }
  eval::OdometryOptions o;
  o.segment_lengths_m = {100, 200};
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, est, o);
  EXPECT_NEAR(m.rotation_deg_per_100m, 0.02 * 180 / M_PI * 1.01, 0.02 * 180 / M_PI * 0.02);
}

TEST(OdometryMetrics, SegmentsMatchABruteForceWalk) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> step(0.2, 2.0);
  std::vector<Eigen::Isometry3d> gt;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < 300; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = p;
    gt.push_back(T);
    p.z() += step(rng);
  }
  eval::OdometryOptions o;
  o.segment_lengths_m = {30, 75};
  o.step_frames = 7;
  const auto segments = eval::segment_errors(gt, gt, o);
  std::size_t k = 0;
  for (int first = 0; first < 300; first += 7) {
    for (double length : o.segment_lengths_m) {
      double travelled = 0;
      int last = -1;
      for (int j = first + 1; j < 300; ++j) {
        travelled += (gt[j].translation() - gt[j - 1].translation()).norm();
        if (travelled > length) {
          last = j;
          break;
        }
      }
      if (last < 0) continue;
      ASSERT_LT(k, segments.size());
      EXPECT_EQ(segments[k].first, first);
      EXPECT_EQ(segments[k].last, last);
      ++k;
    }
  }
  EXPECT_EQ(k, segments.size());
}

TEST(OdometryMetrics, ShortOrMismatchedInput) {
  const auto gt = curvy_drive(50);
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, gt);
  EXPECT_EQ(m.segments, 0);
  EXPECT_TRUE(std::isnan(m.translation_percent));
  EXPECT_THROW(eval::odometry_metrics(gt, curvy_drive(49)), std::invalid_argument);
  EXPECT_THROW(eval::odometry_metrics({gt[0]}, {gt[0]}), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
