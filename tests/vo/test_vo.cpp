// The whole stereo VO on small rendered sequences of the synthetic city (straight line, a
// right turn, blank frames forcing a reset) against the renderer's ground truth.
#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "support/rendered_street.hpp"
#include "support/vo_camera.hpp"

#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"
#include "loopscan/vo/image_points.hpp"
#include "loopscan/vo/stereo_vo.hpp"
namespace loopscan {
namespace {

const test::ShortStreet& scene() {
  static const test::ShortStreet s(1.0);
  return s;
}

cv::Mat render(int frame, int camera_index) { return scene().render(frame, camera_index); }

vo::StereoIntrinsics intrinsics() { return test::vo_intrinsics(scene().camera); }

struct Drive {
  std::vector<vo::FrameResult> frames;
  std::vector<Eigen::Isometry3d> trajectory, gt;  // gt re-anchored at the first frame
  std::vector<vo::FinishedKeyframe> keyframes;
  std::vector<cv::Mat> left;
  int first = 0;
};

// Rendered pairs of the short route, each rendered once.
const cv::Mat& rendered(int frame, int camera_index) {
  static std::map<std::pair<int, int>, cv::Mat> cache;
  cv::Mat& m = cache[{frame, camera_index}];
  if (m.empty()) m = render(frame, camera_index);
  return m;
}

Drive drive(int first, int count, const std::vector<int>& blank = {},
            const vo::VoConfig& config = {}) {
  Drive d;
  d.first = first;
  vo::StereoVo vo(intrinsics(), config);
  const Eigen::Isometry3d T0 = scene().route.T_world_cam[first];
  for (int f = first; f < first + count; ++f) {
    cv::Mat left = rendered(f, 0).clone(), right = rendered(f, 1).clone();
    if (std::find(blank.begin(), blank.end(), f) != blank.end()) {
      left.setTo(0);
      right.setTo(0);
    }
    d.frames.push_back(vo.process(f, left, right));
    d.gt.push_back(T0.inverse() * scene().route.T_world_cam[f]);
    d.left.push_back(left);
  }
  vo.finish();
  d.trajectory = vo.trajectory();
  d.keyframes = vo.finished_keyframes();
  return d;
}

double yaw_change_deg(const std::vector<Eigen::Isometry3d>& T) {
  return Eigen::AngleAxisd(T.front().linear().transpose() * T.back().linear()).angle() * 180 / M_PI;
}

TEST(StereoVo, TracksAStraightStreet) {
  const Drive d = drive(0, 40);
  ASSERT_EQ(d.trajectory.size(), 40u);
  for (const vo::FrameResult& f : d.frames) EXPECT_FALSE(f.reset) << f.frame;
  eval::OdometryOptions o;
  o.segment_lengths_m = {10, 20, 30};
  o.step_frames = 1;
  const eval::OdometryMetrics m = eval::odometry_metrics(d.gt, d.trajectory, o);
  std::printf("straight 39 m: translation %.3f %%, rotation %.3f deg/100 m, ATE %.3f m\n",
              m.translation_percent, m.rotation_deg_per_100m, m.ate_rmse_m);
  EXPECT_LT(m.translation_percent, 1.5);
  EXPECT_LT(m.rotation_deg_per_100m, 3.0);
  EXPECT_LT((d.trajectory.back().translation() - d.gt.back().translation()).norm(), 0.4);
  EXPECT_GE(d.keyframes.size(), 19u);  // the 1.2 m policy at 1 m per frame: every other frame
  EXPECT_LE(d.keyframes.size(), 40u);
}

TEST(StereoVo, TracksARightTurn) {
  // Frames 60..99 of the short route: the end of the first street, a 90-degree right turn
  // (radius 10 m) and the start of the next street.
  const Drive d = drive(60, 40);
  const double turned = yaw_change_deg(d.gt);
  ASSERT_GT(turned, 80.0);
  eval::OdometryOptions o;
  o.segment_lengths_m = {10, 20, 30};
  o.step_frames = 1;
  const eval::OdometryMetrics m = eval::odometry_metrics(d.gt, d.trajectory, o);
  std::printf(
      "turn of %.0f deg over 39 m: translation %.3f %%, rotation %.3f deg/100 m, ATE %.3f m\n",
      turned, m.translation_percent, m.rotation_deg_per_100m, m.ate_rmse_m);
  EXPECT_LT(m.translation_percent, 2.0);
  EXPECT_LT(m.rotation_deg_per_100m, 5.0);
  EXPECT_NEAR(yaw_change_deg(d.trajectory), turned, 1.0);
}

eval::OdometryMetrics metrics_of(const Drive& d) {
  eval::OdometryOptions o;
  o.segment_lengths_m = {10, 20, 30};
  o.step_frames = 1;
  return eval::odometry_metrics(d.gt, d.trajectory, o);
}

// The window's adjustment runs on a worker while the next frame is tracked and lands before
// that frame's pose: the same trajectory, bit for bit, as computing it on the calling thread
// at that point (ba_on_worker = false), every run, whatever the threads' timing.
TEST(StereoVo, TheAdjustmentOnAWorkerGivesTheSameTrajectoryAsOnTheCallingThread) {
  vo::VoConfig here;
  here.ba_on_worker = false;
  for (int first : {0, 60}) {  // the straight street, the right turn
    const Drive worker = drive(first, 40), again = drive(first, 40),
                calling = drive(first, 40, {}, here);
    const eval::OdometryMetrics m = metrics_of(worker);
    std::printf("frames %d..%d: %.3f %%, %.3f deg/100 m, ATE %.3f m\n", first, first + 39,
                m.translation_percent, m.rotation_deg_per_100m, m.ate_rmse_m);
    ASSERT_EQ(worker.trajectory.size(), calling.trajectory.size());
    ASSERT_EQ(worker.trajectory.size(), again.trajectory.size());
    for (std::size_t i = 0; i < worker.trajectory.size(); ++i) {
      EXPECT_TRUE(worker.trajectory[i].matrix() == calling.trajectory[i].matrix()) << i;
      EXPECT_TRUE(worker.trajectory[i].matrix() == again.trajectory[i].matrix()) << i;
    }
  }
}

TEST(StereoVo, ExportedPointsLieOnTheSurfacesWhereTheyWereSelected) {
  const Drive d = drive(0, 12);
  const test::ShortStreet& s = scene();
  const Eigen::Isometry3d T0 = s.route.T_world_cam[0];
  int checked = 0, depth_ok = 0, pixel_ok = 0;
  for (const vo::FinishedKeyframe& kf : d.keyframes) {
    const Eigen::Isometry3d T_gt = s.route.T_world_cam[kf.frame];
    const cv::Mat& image = d.left[kf.frame - d.first];
    ASSERT_GT(kf.camera_points.size(), 200u);
    for (const IdPoint& p : vo::world_points(kf)) EXPECT_EQ(p.id, kf.frame);
    for (const vo::CameraPoint& cp : kf.camera_points) {
      // Into the keyframe's image with its estimated pose: back at the selected pixel.
      const Eigen::Vector3d p_world = kf.T_world_cam * cp.p_cam;
      const Eigen::Vector3d p_cam = kf.T_world_cam.inverse() * p_world;
      EXPECT_NEAR(s.camera.fx * p_cam.x() / p_cam.z() + s.camera.cx, cp.u, 1e-6);
      EXPECT_NEAR(s.camera.fy * p_cam.y() / p_cam.z() + s.camera.cy, cp.v, 1e-6);
      // The gray is the surface's beside the edge: 2 px along the gradient, flatter side.
      const int u = static_cast<int>(cp.u), v = static_cast<int>(cp.v);
      auto gray_at = [&](int x, int y) {
        return static_cast<double>(image.at<std::uint8_t>(y, x));
      };
      auto grad = [&](int x, int y) {
        return std::hypot(0.5 * (gray_at(x + 1, y) - gray_at(x - 1, y)),
                          0.5 * (gray_at(x, y + 1) - gray_at(x, y - 1)));
      };
      const double gx = 0.5 * (gray_at(u + 1, v) - gray_at(u - 1, v));
      const double gy = 0.5 * (gray_at(u, v + 1) - gray_at(u, v - 1));
      const int dx = static_cast<int>(std::lround(2 * gx / std::hypot(gx, gy)));
      const int dy = static_cast<int>(std::lround(2 * gy / std::hypot(gx, gy)));
      const bool a_flatter = grad(u + dx, v + dy) < grad(u - dx, v - dy);
      EXPECT_EQ(cp.gray, a_flatter ? gray_at(u + dx, v + dy) : gray_at(u - dx, v - dy));
      // Through the true pose the point's disparity is one the renderer's rays see within the
      // matching window (window matching puts depth edges on either side of the edge).
      double lo = 1e9, hi = -1e9;
      for (int du = -2; du <= 2; ++du) {
        const Eigen::Vector3d ray = s.camera.ray(cp.u + du, cp.v);
        const auto hit =
            s.world.raycast(T_gt.translation(), T_gt.linear() * ray, 200.0, s.conditions);
        const double disparity = hit ? s.camera.bf / (hit->distance * ray.z()) : 0.0;
        lo = std::min(lo, disparity);
        hi = std::max(hi, disparity);
      }
      const double disparity = s.camera.bf / cp.p_cam.z();
      ++checked;
      if (disparity > lo - 1.0 && disparity < hi + 1.0) ++depth_ok;
      const Eigen::Vector3d in_gt_camera = T_gt.inverse() * (T0 * p_world);
      Eigen::Vector2d px;
      if (s.camera.project(in_gt_camera, px) && (px - Eigen::Vector2d(cp.u, cp.v)).norm() < 2.0)
        ++pixel_ok;
    }
  }
  std::printf(
      "%d points: %.1f %% within 1 px of a true disparity in the window, %.1f %% reproject within "
      "2 px\n",
      checked, 100.0 * depth_ok / checked, 100.0 * pixel_ok / checked);
  EXPECT_GT(depth_ok, 0.95 * checked);
  EXPECT_GT(pixel_ok, 0.9 * checked);
}

// The points are selected on a worker thread: exactly what select_gradient_points gives on the
// keyframe's own images, even though the caller overwrites one pair of buffers every frame.
TEST(StereoVo, ExportedPointsAreTheKeyframeImagesOwnWhenTheCallerReusesItsBuffers) {
  vo::StereoVo vo(intrinsics());
  cv::Mat left, right;
  for (int f = 0; f < 8; ++f) {
    rendered(f, 0).copyTo(left);
    rendered(f, 1).copyTo(right);
    vo.process(f, left, right);
    left.setTo(0);  // at once: the worker is likely still starting
    right.setTo(0);
  }
  vo.finish();
  ASSERT_GE(vo.finished_keyframes().size(), 3u);
  for (const vo::FinishedKeyframe& kf : vo.finished_keyframes()) {
    const std::vector<vo::CameraPoint> expected =
        vo::select_gradient_points(rendered(kf.frame, 0), rendered(kf.frame, 1), intrinsics(), {});
    ASSERT_EQ(kf.camera_points.size(), expected.size()) << kf.frame;
    for (std::size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(kf.camera_points[i].p_cam, expected[i].p_cam);
      EXPECT_EQ(kf.camera_points[i].gray, expected[i].gray);
      EXPECT_EQ(kf.camera_points[i].u, expected[i].u);
      EXPECT_EQ(kf.camera_points[i].v, expected[i].v);
    }
  }
}

TEST(StereoVo, BlankFramesForceAnExplicitResetAndTrackingResumes) {
  const Drive d = drive(0, 36, {18, 19});
  std::vector<int> resets;
  for (const vo::FrameResult& f : d.frames)
    if (f.reset) resets.push_back(f.frame);
  ASSERT_FALSE(resets.empty());
  EXPECT_EQ(resets.front(), 18);
  EXPECT_LE(resets.back(), 21);  // the map is rebuilt on the first textured frame after the gap
  for (int i = 22; i < 36; ++i) EXPECT_GT(d.frames[i].inliers, 50) << i;
  // One world frame throughout: the gap is bridged by the motion model (straight, constant speed).
  EXPECT_LT((d.trajectory.back().translation() - d.gt.back().translation()).norm(), 1.0);
  bool reset_keyframe = false;
  for (const vo::FinishedKeyframe& kf : d.keyframes) reset_keyframe = reset_keyframe || kf.reset;
  EXPECT_TRUE(reset_keyframe);
}

// Every blank frame is a reset bridged by the motion model: through twenty in a row the poses
// stay finite rigid motions and advance by the last velocity.
TEST(StereoVo, ResetsInARowAreBridgedAtTheLastVelocity) {
  std::vector<int> blank;
  for (int f = 14; f < 34; ++f) blank.push_back(f);
  const Drive d = drive(0, 36, blank);
  for (int f = 14; f < 34; ++f) EXPECT_TRUE(d.frames[f].reset) << f;
  const double step =
      (d.frames[14].T_world_cam.translation() - d.frames[13].T_world_cam.translation()).norm();
  EXPECT_NEAR(step, 1.0, 0.1);  // the route's 1 m a frame
  for (int f = 14; f < 34; ++f) {
    const Eigen::Isometry3d& T = d.frames[f].T_world_cam;
    ASSERT_TRUE(T.matrix().allFinite()) << f;
    EXPECT_LT((T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-9)
        << f;
    EXPECT_NEAR((T.translation() - d.frames[f - 1].T_world_cam.translation()).norm(), step, 1e-6)
        << f;
  }
}

TEST(StereoVo, RejectsImagesOfTheWrongSizeAndFramesAfterFinish) {
  vo::StereoVo vo(intrinsics());
  const cv::Mat small(10, 10, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(vo.process(0, small, small), std::invalid_argument);
  vo.finish();
  const cv::Mat black(intrinsics().height, intrinsics().width, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(vo.process(1, black, black), std::logic_error);
}

}  // namespace
}  // namespace loopscan
