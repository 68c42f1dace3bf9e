// Scan imitation: the filters against brute-force oracles, the fast angle binning against
// std::atan2, and the local-map rules (range crop, INIT_FRAME, resets).
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "loopscan/core/descriptors/fast_angle.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/point_filter.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

std::set<std::tuple<double, double, double>> as_set(const Cloud& c) {
  std::set<std::tuple<double, double, double>> s;
  for (const PointI& q : c) s.insert({q.p.x(), q.p.y(), q.p.z()});
  return s;
}

Cloud random_in_range(unsigned seed, int n, double range) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-range, range);
  Cloud c;
  while (static_cast<int>(c.size()) < n) {
    const Eigen::Vector3d p(u(rng), u(rng) * 0.3, u(rng));
    if (p.norm() < range) c.push_back({p, static_cast<float>(std::abs(u(rng)) * 5)});
  }
  return c;
}

// Reference mode in double precision. Default mode runs the single-precision path, checked
// against its own oracle in FloatSoaPathMatchesOracleOnRandomAndBoundaryPoints.
TEST(Filters, CartesianKeepsHighestPointPerVoxelReferenceMode) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Cloud in = random_in_range(seed, 20000, 45.0);
    std::map<std::tuple<int, int, int>, PointI> oracle;
    for (const PointI& q : in) {
      const std::tuple<int, int, int> key{int(std::floor((q.p.x() + 45) / 1.5)),
                                          int(std::floor((q.p.y() + 45) / 0.75)),
                                          int(std::floor((q.p.z() + 45) / 1.5))};
      auto it = oracle.find(key);
      if (it == oracle.end() || q.p.y() < it->second.p.y()) oracle[key] = q;
    }
    Cloud expected;
    for (const auto& kv : oracle) expected.push_back(kv.second);
    {
      const Cloud out = cartesian_filter(in, 45.0, 30, 60, Mode::Reference);
      EXPECT_EQ(out.size(), expected.size());
      EXPECT_EQ(as_set(out), as_set(expected));
    }
  }
}

TEST(Filters, PolarKeepsClosestPointPerCellReferenceMode) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Cloud in = random_in_range(seed, 20000, 45.0);
    std::map<std::pair<int, int>, PointI> oracle;
    const double w = M_PI / 180.0;
    for (const PointI& q : in) {
      const double xz = std::hypot(q.p.x(), q.p.z());
      const std::pair<int, int> key{int(std::floor((std::atan2(q.p.z(), q.p.x()) + M_PI) / w)),
                                    int(std::floor((std::atan2(q.p.y(), xz) + M_PI / 2) / w))};
      auto it = oracle.find(key);
      if (it == oracle.end() || q.p.norm() < it->second.p.norm()) oracle[key] = q;
    }
    Cloud expected;
    for (const auto& kv : oracle) expected.push_back(kv.second);
    EXPECT_EQ(as_set(polar_filter(in, 1.0, Mode::Reference)), as_set(expected));
  }
}

TEST(Filters, EmptyAndSinglePoint) {
  for (Mode mode : {Mode::Reference, Mode::Default}) {
    EXPECT_TRUE(cartesian_filter({}, 45.0, 30, 60, mode).empty());
    EXPECT_TRUE(polar_filter({}, 1.0, mode).empty());
    const Cloud one{{{1, 2, 3}, 9.f}};
    EXPECT_EQ(cartesian_filter(one, 45.0, 30, 60, mode).size(), 1u);
    EXPECT_EQ(polar_filter(one, 1.0, mode).size(), 1u);
  }
}

TEST(FastAngle, BinMatchesExactAtan2IncludingBoundaries) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50, 50);
  const double inv = 180.0 / M_PI;
  for (int i = 0; i < 200000; ++i) {
    double y = u(rng), x = u(rng);
    if (i % 10 == 0) {  // exactly on (or next to) a 1-degree ray
      const double a = (std::floor(u(rng) * 3.6) + (i % 20 == 0 ? 0.0 : 1e-12)) / inv;
      x = std::cos(a) * 10;
      y = std::sin(a) * 10;
    }
    if (i % 1000 == 1) y = 0.0;
    if (i % 1000 == 2) x = 0.0;
    ASSERT_EQ(angle_bin(y, x, M_PI, inv), int(std::floor((std::atan2(y, x) + M_PI) * inv)))
        << "y=" << y << " x=" << x;
  }
  EXPECT_NEAR(approx_atan2(1.0, -1.0), std::atan2(1.0, -1.0), 1e-10);
}

std::vector<IdPoint> points_at(int id, const Eigen::Vector3d& p, int n = 1) {
  return std::vector<IdPoint>(n, IdPoint{id, p, 100.f});
}

TEST(ScanImitator, SkipsInitFramesCropsRangeAndResets) {
  ImitationConfig cfg;
  cfg.init_frames = 3;
  ScanImitator im(cfg);
  Cloud in;
  KeyframePose kf;  // identity: camera at the origin
  const auto near = points_at(0, {1, 0, 10}), far = points_at(0, {0, 0, 100});
  EXPECT_FALSE(im.add_keyframe(kf, near.data(), 1, false, in));
  EXPECT_FALSE(im.add_keyframe(kf, far.data(), 1, false, in));
  EXPECT_FALSE(im.add_keyframe(kf, nullptr, 0, false, in));
  ASSERT_TRUE(im.add_keyframe(kf, nullptr, 0, false, in));
  ASSERT_EQ(in.size(), 1u);            // the far point is out of range ...
  EXPECT_EQ(im.local_map_size(), 1u);  // ... and dropped for good
  KeyframePose moved = kf;
  moved.T_cam_world.col(3) = Eigen::Vector3d(0, 0, -60);  // camera at z = 60: near point far away
  ASSERT_TRUE(im.add_keyframe(moved, nullptr, 0, false, in));
  EXPECT_TRUE(in.empty());
  EXPECT_EQ(im.local_map_size(), 0u);
  EXPECT_FALSE(im.add_keyframe(kf, near.data(), 1, true, in));  // explicit reset
}

TEST(ScanImitator, ReferenceResetsNearOriginDefaultOnlyOnSignal) {
  ImitationConfig cfg;
  cfg.init_frames = 1;
  KeyframePose origin, away;
  away.T_cam_world.col(3) = Eigen::Vector3d(5, 0, 0);
  Cloud in;
  cfg.mode = Mode::Reference;
  ScanImitator ref(cfg);
  EXPECT_FALSE(ref.add_keyframe(away, nullptr, 0, false, in));
  EXPECT_TRUE(ref.add_keyframe(away, nullptr, 0, false, in));
  EXPECT_FALSE(ref.add_keyframe(origin, nullptr, 0, false, in));  // |t| < 1 m: reset
  cfg.mode = Mode::Default;
  ScanImitator def(cfg);
  EXPECT_FALSE(def.add_keyframe(away, nullptr, 0, false, in));
  EXPECT_TRUE(def.add_keyframe(away, nullptr, 0, false, in));
  EXPECT_TRUE(def.add_keyframe(origin, nullptr, 0, false, in));  // passing the origin is fine
}

TEST(ScanImitator, DetectResetsNeedsJumpBackToOrigin) {
  std::vector<KeyframePose> poses(4);
  for (int i = 0; i < 4; ++i) poses[i].id = i;
  poses[1].T_cam_world.col(3) = Eigen::Vector3d(0, 0, -20);   // drove 20 m
  poses[2].T_cam_world.col(3) = Eigen::Vector3d(0, 0, -0.5);  // jumped back: reset
  poses[3].T_cam_world.col(3) = Eigen::Vector3d(0, 0, -0.2);  // near origin, no jump
  EXPECT_EQ(detect_vo_resets(poses), std::vector<int>{2});
}

TEST(DescribeSequence, FewerKeyframesThanInitFrameGivesNoSignature) {
  std::vector<KeyframePose> poses(10);
  for (int i = 0; i < 10; ++i) poses[i].id = i;
  const auto pts = points_at(0, {1, 0, 10}, 50);
  for (Mode mode : {Mode::Reference, Mode::Default}) {
    const auto out =
        describe_sequence(poses, pts, SequenceOptions::make(Method::ScanContext, mode));
    EXPECT_TRUE(out.signatures.empty());
    EXPECT_TRUE(out.keyframe_ids.empty());
  }
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

TEST(FastAngle, TableBinnerMatchesExactFormulaForEveryUsedWidth) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-50, 50);
  for (double width_deg : {1.0, 6.0, 22.5, 0.5, 7.0 /* not dividing 90: generic path */}) {
    const double inv = 180.0 / (width_deg * M_PI);
    for (double offset : {M_PI, M_PI / 2}) {
      const AngleBinner binner(inv, offset);
      for (int i = 0; i < 100000; ++i) {
        double y = u(rng), x = u(rng);
        if (i % 7 == 0) {  // on a bin boundary, or within a hair of it
          const double a = std::floor(u(rng) / width_deg) * width_deg * M_PI / 180.0 +
                           (i % 14 == 0 ? 0.0 : 1e-13 * (i % 3 - 1));
          x = 10 * std::cos(a);
          y = 10 * std::sin(a);
        }
        if (i % 500 == 1) y = (i % 1000 == 1) ? 0.0 : -0.0;
        if (i % 500 == 2) x = 0.0;
        const int exact = int(std::floor((std::atan2(y, x) + offset) * inv));
        ASSERT_EQ(binner(y, x), exact) << "width " << width_deg << " y=" << y << " x=" << x;
      }
    }
  }
}

}  // namespace
}  // namespace loopscan

#include "loopscan/core/scan/camera_points.hpp"

namespace loopscan {
namespace {

// The single-precision SoA path against a brute-force oracle evaluating the same cell
// formulas on the same float inputs (Cartesian in float arithmetic, polar with exact atan2).
TEST(Filters, FloatSoaPathMatchesOracleOnRandomAndBoundaryPoints) {
  for (unsigned seed = 1; seed <= 4; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-44.f, 44.f);
    CameraPoints pts;
    while (pts.size() < 20003) {  // not a multiple of the vector width: exercises the tail
      float x = u(rng), y = u(rng) * 0.3f, z = u(rng);
      if (pts.size() % 50 == 0) {  // exactly on a 1-degree azimuth ray
        const double a = std::floor(u(rng)) * M_PI / 180.0;
        x = static_cast<float>(20 * std::cos(a));
        z = static_cast<float>(20 * std::sin(a));
      }
      if (x * x + y * y + z * z >= 44.f * 44.f) continue;
      pts.x.push_back(x);
      pts.y.push_back(y);
      pts.z.push_back(z);
      pts.gray.push_back(static_cast<float>(pts.size() % 256));
    }
    const ImitationConfig cfg;
    for (ScanFilter filter : {ScanFilter::Cartesian, ScanFilter::Polar}) {
      std::map<long, std::pair<double, std::size_t>> best;  // key -> (score, index)
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const float x = pts.x[i], y = pts.y[i], z = pts.z[i];
        long key;
        double score;
        if (filter == ScanFilter::Cartesian) {
          const float s = static_cast<float>(1.0 / 1.5), sy = static_cast<float>(1.0 / 0.75);
          key = long((x + 45.f) * s) + 61 * long((y + 45.f) * sy) + 61 * 121 * long((z + 45.f) * s);
          score = y;
        } else {
          const float xz2 = x * x + z * z;
          const double inv = 180.0 / M_PI;
          key = long(std::floor((std::atan2(double(z), double(x)) + M_PI) * inv)) +
                361 * long(std::floor((std::atan2(double(y), double(std::sqrt(xz2))) + M_PI / 2) *
                                      inv));
          score = xz2 + y * y;
        }
        auto it = best.find(key);
        if (it == best.end() || score < it->second.first) best[key] = {score, i};
      }
      std::set<std::tuple<double, double, double>> expected;
      for (const auto& kv : best) {
        const std::size_t i = kv.second.second;
        expected.insert({pts.x[i], pts.y[i], pts.z[i]});
      }
      const Cloud out = filter_camera_points(pts, filter, cfg);
      EXPECT_EQ(out.size(), expected.size());
      EXPECT_EQ(as_set(out), expected) << "filter " << int(filter) << " seed " << seed;
    }
  }
}

}  // namespace
}  // namespace loopscan
