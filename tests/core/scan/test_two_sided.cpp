// Two-sided scans: a keyframe waits until the VO is lookahead_m past it, its scan then holds
// the points of the keyframes after it; resets and the end of a drive describe the waiting ones.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <vector>

#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {
namespace {

// Keyframe i: camera at world z = i metres, looking along +z; it exports one point 5 m ahead.
KeyframePose keyframe_at(int i) {
  KeyframePose k;
  k.id = i;
  k.T_cam_world.col(3) = Eigen::Vector3d(0, 0, -i);
  return k;
}

std::vector<IdPoint> ahead_of(int i) { return {IdPoint{i, {1.0, 0.0, i + 5.0}, 100.f}}; }

ImitationConfig two_sided(double lookahead) {
  ImitationConfig c;
  c.lookahead_m = lookahead;
  return c;
}

bool holds_point_at_z(const ReadyScan& r, double z) {
  for (std::size_t i = 0; i < r.in_range.size(); ++i) {
    if (std::abs(r.in_range.z[i] - z) < 1e-4) return true;
  }
  return false;
}

TEST(TwoSidedScan, WaitsLookaheadMetresAndHoldsLaterPoints) {
  ScanImitator im(two_sided(10.0));
  std::vector<ReadyScan> ready;
  for (int i = 0; i < 10; ++i) {
    const auto p = ahead_of(i);
    im.push(keyframe_at(i), p.data(), p.size(), false, ScanFilter::Polar, ready);
  }
  EXPECT_TRUE(ready.empty());  // 9 m travelled: keyframe 0 still waits
  EXPECT_EQ(im.waiting(), 10u);
  const auto p = ahead_of(10);
  im.push(keyframe_at(10), p.data(), p.size(), false, ScanFilter::Polar, ready);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].keyframe.id, 0);  // no INIT_FRAME gap
  // The point keyframe 10 exported (world z = 15) is in keyframe 0's scan, at camera z = 15.
  EXPECT_TRUE(holds_point_at_z(ready[0], 15.0));
  EXPECT_EQ(ready[0].in_range.size(), 11u);
  EXPECT_FALSE(ready[0].scan.empty());
}

TEST(TwoSidedScan, ResetAndFinishDescribeEveryWaitingKeyframeInOrder) {
  ScanImitator im(two_sided(10.0));
  std::vector<ReadyScan> ready;
  for (int i = 0; i < 15; ++i) {
    const auto p = ahead_of(i);
    im.push(keyframe_at(i), p.data(), p.size(), false, ScanFilter::Cartesian, ready);
  }
  ASSERT_EQ(ready.size(), 5u);  // keyframes 0..4
  ready.clear();
  // A reset: keyframes 5..14 are described from the map before it is forgotten.
  const auto p = ahead_of(100);
  im.push(keyframe_at(100), p.data(), p.size(), true, ScanFilter::Cartesian, ready);
  ASSERT_EQ(ready.size(), 10u);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(ready[k].keyframe.id, 5 + k);
  EXPECT_TRUE(holds_point_at_z(ready[0], 14.0 + 5.0 - 5.0));  // keyframe 14's point
  EXPECT_FALSE(holds_point_at_z(ready[9], 105.0 - 14.0));     // nothing from after the reset
  EXPECT_EQ(im.waiting(), 1u);
  ready.clear();
  im.finish(ScanFilter::Cartesian, ready);
  ASSERT_EQ(ready.size(), 1u);
  EXPECT_EQ(ready[0].keyframe.id, 100);
  EXPECT_EQ(ready[0].in_range.size(), 1u);
  EXPECT_EQ(im.waiting(), 0u);
}

TEST(TwoSidedScan, PointsOutOfRangeOfTheWaitingStretchLeaveTheMap) {
  ImitationConfig c = two_sided(5.0);
  c.range_m = 20.0;
  ScanImitator im(c);
  std::vector<ReadyScan> ready;
  for (int i = 0; i < 60; ++i) {
    const auto p = ahead_of(i);
    im.push(keyframe_at(i), p.data(), p.size(), false, ScanFilter::Polar, ready);
  }
  // Kept: points within 20 m of keyframe 59 or of the oldest waiting keyframe (55; 54 was
  // described when 59 arrived): z in (35.03, 78.97) -> exported by keyframes 31..59.
  EXPECT_EQ(im.local_map_size(), 29u);
}

TEST(TwoSidedScan, ReferenceModeAndZeroLookaheadStayForwardOnly) {
  for (Mode mode : {Mode::Reference, Mode::Default}) {
    ImitationConfig c = two_sided(mode == Mode::Reference ? 10.0 : 0.0);
    c.mode = mode;
    c.init_frames = 3;
    ScanImitator a(c);
    ImitationConfig plain;
    plain.mode = mode;
    plain.init_frames = 3;
    ScanImitator b(plain);
    std::vector<ReadyScan> ready;
    for (int i = 1; i < 12; ++i) {  // from z = 1: the reference's reset heuristic stays quiet
      const auto p = ahead_of(i);
      ready.clear();
      a.push(keyframe_at(i), p.data(), p.size(), false, ScanFilter::Polar, ready);
      Cloud scan;
      const bool got =
          b.next_scan(keyframe_at(i), p.data(), p.size(), false, ScanFilter::Polar, scan);
      ASSERT_EQ(ready.size(), got ? 1u : 0u) << i;
      if (!got) continue;
      EXPECT_EQ(ready[0].keyframe.id, i);
      ASSERT_EQ(ready[0].scan.size(), scan.size());
      for (std::size_t k = 0; k < scan.size(); ++k) EXPECT_EQ(ready[0].scan[k].p, scan[k].p);
    }
  }
}

TEST(TwoSidedScan, LookaheadIsValidated) {
  EXPECT_THROW(ScanImitator{two_sided(-1.0)}, std::invalid_argument);
  EXPECT_THROW(ScanImitator{two_sided(NAN)}, std::invalid_argument);
}

TEST(DescriptorFrame, CameraAndCentroidFramesKeepUpAndAreRightHanded) {
  Cloud cloud;
  for (int i = 0; i <= 20; ++i) {  // two facades, 4 m left and 10 m right of the camera
    cloud.push_back({{-4.0, -1.0 * (i % 5), i - 10.0}, 10.f});
    cloud.push_back({{10.0, -1.0 * (i % 5), i - 10.0}, 10.f});
  }
  for (DescriptorFrame f :
       {DescriptorFrame::Camera, DescriptorFrame::Centroid, DescriptorFrame::GravityPca}) {
    Eigen::Matrix3d axes;
    const Cloud out = align_scan(cloud, f, Mode::Default, &axes);
    EXPECT_NEAR(axes.determinant(), 1.0, 1e-12);
    EXPECT_TRUE(axes.row(0).isApprox(Eigen::RowVector3d(0, -1, 0)));  // up = -y
    if (f != DescriptorFrame::GravityPca) {
      EXPECT_NEAR(out[0].p(0), 0.0, 1e-12);  // height kept
    }
  }
  // Centroid: the middle of the street (x = 3), whichever side the camera drives on.
  const Cloud centred = align_scan(cloud, DescriptorFrame::Centroid, Mode::Default);
  EXPECT_NEAR(centred[0].p(1), -7.0, 1e-9);
  EXPECT_NEAR(centred[1].p(1), 7.0, 1e-9);
  EXPECT_EQ(parse_descriptor_frame("centroid"), DescriptorFrame::Centroid);
  EXPECT_THROW(parse_descriptor_frame("gravity"), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
