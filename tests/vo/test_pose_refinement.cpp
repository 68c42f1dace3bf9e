// The uncertainty-weighted pose refinement against known answers: exact data, OpenCV's
// unweighted Levenberg-Marquardt as the oracle when every point is exact, the covariance of a
// stereo point against finite differences, and noise drawn from the covariances it models.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "loopscan/vo/image_points.hpp"
#include "loopscan/vo/pose_refinement.hpp"

namespace loopscan {
namespace {

using Twist = Eigen::Matrix<double, 6, 1>;

Eigen::Isometry3d pose_from(double yaw_deg, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// Points in front of the camera at T_cam_world, 3-60 m deep, inside the image.
std::vector<vo::UncertainPoint> scene(const Eigen::Isometry3d& T_cam_world,
                                      const vo::StereoIntrinsics& c, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(20, c.width - 20), v(20, c.height - 20), z(3, 60);
  std::vector<vo::UncertainPoint> points;
  for (int i = 0; i < n; ++i) {
    const double depth = z(rng);
    const Eigen::Vector3d p_cam((u(rng) - c.cx) * depth / c.fx, (v(rng) - c.cy) * depth / c.fy,
                                depth);
    points.push_back({T_cam_world.inverse() * p_cam, Eigen::Matrix3d::Zero()});
  }
  return points;
}

Eigen::Vector2d project(const vo::StereoIntrinsics& c, const Eigen::Vector3d& p) {
  return {c.fx * p.x() / p.z() + c.cx, c.fy * p.y() / p.z() + c.cy};
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd((a.linear().transpose() * b.linear())).angle() * 180 / M_PI;
}

TEST(PoseRefinement, ExactObservationsGiveTheTruePoseFromAPerturbedStart) {
  const vo::StereoIntrinsics c;
  std::mt19937 rng(5);
  const Eigen::Isometry3d truth = pose_from(7, {0.4, -0.1, -3.0});
  const auto points = scene(truth, c, 60, rng);
  std::vector<Eigen::Vector2d> obs;
  for (const auto& p : points) obs.push_back(project(c, truth * p.position));
  Eigen::Isometry3d T = pose_from(9, {0.1, 0.1, -2.2});
  ASSERT_TRUE(vo::refine_pose(T, points, obs, c));
  EXPECT_LT((T.translation() - truth.translation()).norm(), 1e-8);
  EXPECT_LT(rotation_error_deg(T, truth), 1e-7);
}

// With exact points and no robust loss the weights are all equal: ordinary least squares on
// the reprojections, which OpenCV's Levenberg-Marquardt also minimises.
TEST(PoseRefinement, ExactPointsMatchOpenCvsLeastSquares) {
  const vo::StereoIntrinsics c;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    const Eigen::Isometry3d truth = pose_from(-4.0 + seed, {0.2 * seed, 0.05, -1.5 * seed});
    const auto points = scene(truth, c, 80, rng);
    std::normal_distribution<double> noise(0, 1.5);
    std::vector<Eigen::Vector2d> obs;
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const auto& p : points) {
      obs.push_back(project(c, truth * p.position) + Eigen::Vector2d(noise(rng), noise(rng)));
      object.emplace_back(p.position.x(), p.position.y(), p.position.z());
      image.emplace_back(obs.back().x(), obs.back().y());
    }
    vo::PoseRefinementConfig config;
    config.huber_mahalanobis = 1e12;
    config.iterations = 30;
    Eigen::Isometry3d T = truth;
    ASSERT_TRUE(vo::refine_pose(T, points, obs, c, config));

    const Eigen::AngleAxisd start(truth.linear());
    const Eigen::Vector3d r0 = start.angle() * start.axis();
    cv::Mat rvec = (cv::Mat_<double>(3, 1) << r0.x(), r0.y(), r0.z());
    cv::Mat tvec = (cv::Mat_<double>(3, 1) << truth.translation().x(), truth.translation().y(),
                    truth.translation().z());
    const cv::Matx33d K(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
    cv::solvePnPRefineLM(
        object, image, K, cv::noArray(), rvec, tvec,
        cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-12));
    const Eigen::Vector3d t_cv(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    const Eigen::Vector3d r_cv(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
    const Eigen::Matrix3d R_cv =
        Eigen::AngleAxisd(r_cv.norm(), r_cv.normalized()).toRotationMatrix();
    EXPECT_LT((T.translation() - t_cv).norm(), 1e-6) << "seed " << seed;
    EXPECT_LT(Eigen::AngleAxisd(T.linear().transpose() * R_cv).angle(), 1e-8) << "seed " << seed;
    // And the noise did move it off the truth, so the comparison is not trivially at the start.
    EXPECT_GT((T.translation() - truth.translation()).norm(), 1e-4) << "seed " << seed;
  }
}

TEST(PoseRefinement, StereoPointCovarianceIsTheLinearisedBackProjection) {
  const vo::StereoIntrinsics c;
  const double u = 900, v = 100, d = 9.5, s_px = 0.7, s_d = 0.4, h = 1e-5;
  const Eigen::Matrix3d cov = vo::stereo_point_covariance(c, u, v, d, s_px, s_d);
  Eigen::Matrix3d J;
  J.col(0) = (vo::back_project(c, u + h, v, d) - vo::back_project(c, u - h, v, d)) / (2 * h);
  J.col(1) = (vo::back_project(c, u, v + h, d) - vo::back_project(c, u, v - h, d)) / (2 * h);
  J.col(2) = (vo::back_project(c, u, v, d + h) - vo::back_project(c, u, v, d - h)) / (2 * h);
  const Eigen::Matrix3d expected =
      J * Eigen::Vector3d(s_px * s_px, s_px * s_px, s_d * s_d).asDiagonal() * J.transpose();
  EXPECT_LT((cov - expected).norm(), 1e-6 * expected.norm());
  // Depth variance grows with the fourth power of depth: (bf / d^2)^2 s_d^2.
  EXPECT_NEAR(cov(2, 2), std::pow(c.bf() / (d * d) * s_d, 2), 1e-9);
}

// Points triangulated by a stereo pair elsewhere carry depth errors drawn from their covariance;
// the camera sees them from 6 m further on and to the side. Weighting each by its covariance
// carried into the image recovers the pose better than treating the points as exact.
TEST(PoseRefinement, WeightingByStereoCovarianceBeatsTreatingPointsAsExact) {
  const vo::StereoIntrinsics c;
  const double s_px = 0.5, s_d = 0.5;
  std::mt19937 rng(11);
  std::normal_distribution<double> unit(0, 1);
  double weighted = 0, unweighted = 0;
  int better = 0;
  const int trials = 40;
  for (int trial = 0; trial < trials; ++trial) {
    // Triangulated at the origin (world = first camera), seen from the second pose.
    const Eigen::Isometry3d truth = pose_from(3, {-1.0, 0.0, -6.0});  // world to camera
    std::uniform_real_distribution<double> u(20, c.width - 20), v(20, c.height - 20), z(8, 70);
    std::vector<vo::UncertainPoint> points;
    std::vector<Eigen::Vector2d> obs;
    while (points.size() < 60) {
      const double depth = z(rng);
      const double pu = u(rng), pv = v(rng), d = c.bf() / depth;
      const Eigen::Vector3d p = vo::back_project(c, pu, pv, d);
      const Eigen::Vector3d seen = truth * p;
      if (seen.z() < 1) continue;
      const Eigen::Vector2d px = project(c, seen);
      if (px.x() < 0 || px.x() >= c.width || px.y() < 0 || px.y() >= c.height) continue;
      // The stereo pair measured u, v and d with noise; the camera tracks with noise.
      const double mu = pu + s_px * unit(rng), mv = pv + s_px * unit(rng);
      const double md = std::max(0.2, d + s_d * unit(rng));
      points.push_back(
          {vo::back_project(c, mu, mv, md), vo::stereo_point_covariance(c, mu, mv, md, s_px, s_d)});
      obs.push_back(px + s_px * Eigen::Vector2d(unit(rng), unit(rng)));
    }
    std::vector<vo::UncertainPoint> exact = points;
    for (auto& p : exact) p.covariance.setZero();
    vo::PoseRefinementConfig config;
    config.sigma_px = s_px;
    Eigen::Isometry3d a = truth, b = truth;
    ASSERT_TRUE(vo::refine_pose(a, points, obs, c, config));
    ASSERT_TRUE(vo::refine_pose(b, exact, obs, c, config));
    const double ea = (a.inverse().translation() - truth.inverse().translation()).norm();
    const double eb = (b.inverse().translation() - truth.inverse().translation()).norm();
    weighted += ea;
    unweighted += eb;
    better += ea < eb;
  }
  EXPECT_LT(weighted, 0.8 * unweighted) << weighted / trials << " vs " << unweighted / trials;
  EXPECT_GT(better, trials / 2);
}

// A fifth of the tracks are gross outliers (20-60 px off): with the Huber loss the pose stays
// near the truth, and an unbounded squared loss is pulled far off by the same data.
TEST(PoseRefinement, TheRobustLossResistsGrossOutliers) {
  const vo::StereoIntrinsics c;
  std::mt19937 rng(21);
  const Eigen::Isometry3d truth = pose_from(5, {0.5, -0.2, -4.0});
  const auto points = scene(truth, c, 100, rng);
  std::normal_distribution<double> noise(0, 0.5);
  std::uniform_real_distribution<double> gross(20, 60);
  std::vector<Eigen::Vector2d> obs;
  for (std::size_t i = 0; i < points.size(); ++i) {
    obs.push_back(project(c, truth * points[i].position) + Eigen::Vector2d(noise(rng), noise(rng)));
    if (i % 5 == 0) obs.back() += Eigen::Vector2d(gross(rng), gross(rng));
  }
  const Eigen::Isometry3d start = pose_from(6, {0.4, -0.1, -3.8});
  vo::PoseRefinementConfig robust, squared;
  robust.iterations = squared.iterations = 30;
  squared.huber_mahalanobis = 1e12;
  Eigen::Isometry3d a = start, b = start;
  ASSERT_TRUE(vo::refine_pose(a, points, obs, c, robust));
  ASSERT_TRUE(vo::refine_pose(b, points, obs, c, squared));
  const double ea = (a.translation() - truth.translation()).norm();
  const double eb = (b.translation() - truth.translation()).norm();
  EXPECT_LT(ea, 0.05);
  EXPECT_GT(eb, 3 * ea);
}

TEST(PoseRefinement, MismatchedSizesAreRefused) {
  const vo::StereoIntrinsics c;
  std::mt19937 rng(2);
  const auto points = scene(Eigen::Isometry3d::Identity(), c, 10, rng);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EXPECT_FALSE(vo::refine_pose(T, points, std::vector<Eigen::Vector2d>(9), c));
}

TEST(PoseRefinement, TooFewPointsInFrontLeaveThePoseUnchanged) {
  const vo::StereoIntrinsics c;
  const Eigen::Isometry3d start = pose_from(2, {0, 0, 1});
  Eigen::Isometry3d T = start;
  const Eigen::Matrix3d exact = Eigen::Matrix3d::Zero();
  const std::vector<vo::UncertainPoint> points = {
      {{0, 0, 5}, exact}, {{1, 0, 6}, exact}, {{0, 0, -5}, exact}};
  const std::vector<Eigen::Vector2d> obs(3, Eigen::Vector2d(600, 180));
  EXPECT_FALSE(vo::refine_pose(T, points, obs, c));
  EXPECT_TRUE(T.isApprox(start));
}

}  // namespace
}  // namespace loopscan
