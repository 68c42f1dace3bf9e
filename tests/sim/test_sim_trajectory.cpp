// Trajectories (built-in routes, KITTI, RobotCar GPS), keyframe policy and the stereo camera.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "loopscan/sim/camera.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"
#include "support/test_support.hpp"

namespace loopscan::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Declares `var` as a file of the shared data folder; skips the test when it is absent.
#define REQUIRE_SHARED_FILE(var, relative)                       \
  const std::string var = test::shared_dir() + "/" + (relative); \
  LOOPSCAN_SKIP_WITHOUT_SHARED(std::filesystem::exists(var), var)

double yaw_between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return std::abs(std::remainder(heading_yaw(a) - heading_yaw(b), 2 * kPi));
}

double max_yaw_jump(const Trajectory& t) {
  double m = 0.0;
  for (std::size_t i = 1; i < t.T_world_cam.size(); ++i) {
    m = std::max(m, yaw_between(t.T_world_cam[i], t.T_world_cam[i - 1]));
  }
  return m;
}

void expect_level(const Trajectory& t) {
  for (const Eigen::Isometry3d& T : t.T_world_cam) {
    ASSERT_LT((T.linear().col(1) - Eigen::Vector3d::UnitY()).norm(), 1e-9);  // y stays down
    ASSERT_LT((T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  }
}

// Length in range, ~1 m per frame without jumps, smooth heading, level camera along the motion.
void expect_drivable(const Trajectory& t, double min_length_m, double max_length_m) {
  const std::vector<Eigen::Vector3d> c = t.centres();
  double length = 0.0;
  for (std::size_t i = 1; i < c.size(); ++i) {
    const Eigen::Vector3d step = c[i] - c[i - 1];
    length += step.norm();
    ASSERT_LT(step.norm(), 2.0) << "frame " << i;
    ASSERT_GT(step.normalized().dot(t.T_world_cam[i].linear().col(2)), std::cos(10 * kDeg));
  }
  EXPECT_GT(length, min_length_m);
  EXPECT_LT(length, max_length_m);
  EXPECT_NEAR(length / static_cast<double>(c.size() - 1), 1.0, 0.1);
  EXPECT_LT(max_yaw_jump(t), 15.0 * kDeg);
  expect_level(t);
}

struct Revisits {
  int pairs = 0;     // frame pairs >= min_gap apart and within the radius
  int opposite = 0;  // those of them with headings more than 150 deg apart
};

Revisits find_revisits(const Trajectory& t, int min_gap = 100, double radius = 5.0) {
  Revisits r;
  const std::vector<Eigen::Vector3d> c = t.centres();
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (std::size_t j = i + min_gap; j < c.size(); ++j) {
      if ((c[i] - c[j]).norm() > radius) continue;
      ++r.pairs;
      r.opposite += yaw_between(t.T_world_cam[i], t.T_world_cam[j]) > 150.0 * kDeg;
    }
  }
  return r;
}

// Every keyframe triggers the policy against the previous one, and no frame in between does.
void expect_policy_holds(const Trajectory& t, const std::vector<int>& kf,
                         const KeyframeSelection& s) {
  ASSERT_TRUE(!kf.empty() && kf.front() == 0);
  auto triggers = [&](int a, int b) {
    const double moved = (t.T_world_cam[b].translation() - t.T_world_cam[a].translation()).norm();
    return moved > s.min_distance_m ||
           rotation_angle(t.T_world_cam[a], t.T_world_cam[b]) > s.min_rotation_deg * kDeg;
  };
  const int n = static_cast<int>(t.T_world_cam.size());
  for (std::size_t k = 0; k < kf.size(); ++k) {
    const int next = k + 1 < kf.size() ? kf[k + 1] : n;
    for (int i = kf[k] + 1; i < next; ++i) ASSERT_FALSE(triggers(kf[k], i)) << "frame " << i;
    ASSERT_TRUE(next == n || triggers(kf[k], next)) << "keyframe " << next;
  }
}

std::vector<Eigen::Matrix<double, 3, 4>> read_kitti_poses(const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Matrix<double, 3, 4>> poses;
  for (std::string line; std::getline(in, line);) {
    std::istringstream row(line);
    Eigen::Matrix<double, 3, 4> P;
    for (int k = 0; k < 12; ++k) row >> P(k / 4, k % 4);
    if (row) poses.push_back(P);
  }
  return poses;
}

TEST(SimTrajectory, CityLengthSpacingAndHeading) {
  const Trajectory t = make_builtin_trajectory("city");
  EXPECT_EQ(t.name, "city");
  expect_drivable(t, 1800.0, 2400.0);
}

TEST(SimTrajectory, CityRevisitsIncludeOppositeDirection) {
  const Revisits r = find_revisits(make_builtin_trajectory("city"));
  EXPECT_GT(r.pairs, 200);
  EXPECT_GT(r.opposite, 500);  // a whole street driven both ways, not just two corners
}

TEST(SimTrajectory, ShortRouteHasOneRevisit) {
  const Trajectory t = make_builtin_trajectory("short");
  expect_drivable(t, 300.0, 400.0);
  EXPECT_GT(find_revisits(t).pairs, 20);
}

TEST(SimTrajectory, LapsDriveTheRouteAgainThroughADrivableConnector) {
  for (const std::string name : {"city", "short", "reverse"}) {
    SCOPED_TRACE(name);
    const Trajectory route = make_builtin_trajectory(name);
    const std::size_t n = route.T_world_cam.size();
    const std::vector<Eigen::Isometry3d> connector = connector_back_to_start(route);
    const Trajectory laps = drive_laps(route, 3);
    ASSERT_EQ(laps.T_world_cam.size(), 3 * n + 2 * connector.size());
    // Every lap is the route itself, frame for frame.
    for (std::size_t lap = 0; lap < 3; ++lap) {
      const std::size_t first = lap * (n + connector.size());
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_TRUE(laps.T_world_cam[first + i].isApprox(route.T_world_cam[i], 1e-12)) << i;
    }
    // The route ends away from its start: the connector is a real drive back, no shorter than
    // the gap and no detour (at most the gap plus two full turns), and the whole thing is
    // drivable (steps ~1 m, heading along the motion, smooth, level).
    const double gap =
        (route.T_world_cam.front().translation() - route.T_world_cam.back().translation()).norm();
    EXPECT_GT(connector.size() + 1, gap * 0.99);
    const double turns = 4 * kPi * lap_connector_turn_radius_m;
    EXPECT_LT(connector.size() + 1, gap + turns);
    double route_length = 0;
    for (std::size_t i = 1; i < n; ++i)
      route_length +=
          (route.T_world_cam[i].translation() - route.T_world_cam[i - 1].translation()).norm();
    expect_drivable(laps, 3 * route_length + 2 * gap, 3 * route_length + 2 * (gap + turns));
  }
  EXPECT_EQ(drive_laps(make_builtin_trajectory("short"), 1).T_world_cam.size(),
            make_builtin_trajectory("short").T_world_cam.size());
}

TEST(SimTrajectory, LapsOfALoopNeedNoConnectorAndBadLapsAreRefused) {
  Trajectory circle;
  constexpr int kFrames = 314;  // 50 m radius at ~1 m a frame
  for (int i = 0; i < kFrames; ++i) {
    const double a = 2 * kPi * i / kFrames;
    // Driving anticlockwise seen from above (x east, z north): heading = tangent.
    circle.T_world_cam.push_back(
        level_pose(50.0 * Eigen::Vector3d(std::sin(a), 0, std::cos(a)), a + kPi / 2));
  }
  EXPECT_TRUE(connector_back_to_start(circle).empty());
  EXPECT_EQ(drive_laps(circle, 4).T_world_cam.size(), 4u * kFrames);
  expect_drivable(drive_laps(circle, 4), 4 * 2 * kPi * 50 * 0.99, 4 * 2 * kPi * 50 * 1.01);
  EXPECT_THROW(drive_laps(circle, 0), std::invalid_argument);
  Trajectory one;
  one.T_world_cam.push_back(Eigen::Isometry3d::Identity());
  EXPECT_THROW(drive_laps(one, 2), std::invalid_argument);
  one.T_world_cam.push_back(Eigen::Isometry3d::Identity());
  EXPECT_THROW(drive_laps(one, 2), std::invalid_argument);  // does not move
}

TEST(SimTrajectory, UnknownRouteNameListsBuiltins) {
  try {
    make_builtin_trajectory("nowhere");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("city, short"), std::string::npos) << e.what();
  }
}

TEST(SimTrajectory, KeyframesOnCityFollowPolicy) {
  const Trajectory t = make_builtin_trajectory("city");
  const std::vector<int> kf = select_keyframes(t);
  expect_policy_holds(t, kf, {});
  // ~1 m per frame: every second frame on straights, every frame in the tighter turns.
  EXPECT_GT(kf.size(), t.T_world_cam.size() / 2);
  EXPECT_LT(kf.size(), t.T_world_cam.size() * 3 / 4);
}

TEST(SimTrajectory, Kitti06CentresAndKeyframes) {
  REQUIRE_SHARED_FILE(path, "data/kitti/poses/06.txt");
  const auto poses = read_kitti_poses(path);
  ASSERT_EQ(poses.size(), 1101u);
  const Trajectory t = trajectory_from_kitti(poses, "kitti06");
  const std::vector<Eigen::Vector3d> c = t.centres();
  ASSERT_EQ(c.size(), poses.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(c[i], poses[i].col(3)) << "frame " << i;
    ASSERT_EQ(t.T_world_cam[i].linear(), poses[i].leftCols<3>()) << "frame " << i;
  }
  // The real SO-DSO run kept 910 of 1101 frames.
  const std::vector<int> kf = select_keyframes(t);
  EXPECT_GE(kf.size(), 800u);
  EXPECT_LE(kf.size(), 1050u);
  expect_policy_holds(t, kf, {});
  const KeyframeSelection loose{3.0, 15.0};  // a looser policy keeps far fewer
  const std::vector<int> fewer = select_keyframes(t, loose);
  EXPECT_LT(fewer.size(), kf.size() / 2);
  expect_policy_holds(t, fewer, loose);
}

TEST(SimTrajectory, GpsStraightLineHeadingAndLevel) {
  // 200 m along a bearing of 30 deg east of north, 0.5 m per row, with a stop (duplicates) in
  // the middle and a slow climb; origin far from zero as in real UTM rows.
  const double bearing = 30.0 * kDeg;
  const Eigen::Vector3d origin(5735891.8, 620126.3, -108.8);
  std::vector<Eigen::Vector3d> ned;
  for (int i = 0; i <= 400; ++i) {
    ned.insert(ned.end(), i == 200 ? 20 : 1,
               origin + 0.5 * i * Eigen::Vector3d(std::cos(bearing), std::sin(bearing), -0.01));
  }
  const Trajectory t = trajectory_from_gps(ned, "line");
  ASSERT_EQ(t.T_world_cam.size(), ned.size());
  expect_level(t);
  for (std::size_t i = 0; i < ned.size(); ++i) {
    const Eigen::Vector3d d = ned[i] - origin;
    ASSERT_LT((t.T_world_cam[i].translation() - Eigen::Vector3d(d.y(), d.z(), d.x())).norm(), 1e-9);
    // Yaw about the down axis from north (+z) towards east (+x) equals the bearing.
    ASSERT_NEAR(heading_yaw(t.T_world_cam[i]), bearing, 1e-6) << "frame " << i;
  }
  // x east, y down, z north is right-handed: the camera's right points east-south-east.
  const Eigen::Vector3d right(std::cos(bearing), 0.0, -std::sin(bearing));
  EXPECT_LT((t.T_world_cam[0].linear().col(0) - right).norm(), 1e-9);
  ned[7].x() = std::nan("");
  EXPECT_THROW(trajectory_from_gps(ned, "bad"), std::invalid_argument);
  EXPECT_TRUE(trajectory_from_gps({}, "empty").T_world_cam.empty());
}

TEST(SimTrajectory, GpsHeadingIgnoresPositionJumps) {
  // Northwards at 0.15 m per row with a 1.2 m eastward fix correction every 16 rows, as in the
  // RobotCar INS tracks: the heading must stay north, not swing towards each jump.
  std::vector<Eigen::Vector3d> ned;
  Eigen::Vector3d p(100.0, 200.0, 0.0);
  for (int i = 0; i < 600; ++i) {
    p.x() += 0.15;
    if (i % 16 == 15) p.y() += 1.2;
    ned.push_back(p);
  }
  const Trajectory t = trajectory_from_gps(ned, "jumps");
  for (std::size_t i = 0; i < ned.size(); ++i) {
    ASSERT_NEAR(heading_yaw(t.T_world_cam[i]), 0.0, 1e-6) << "frame " << i;
  }
}

TEST(SimTrajectory, RobotCarGpsLoadsWithContinuousHeading) {
  REQUIRE_SHARED_FILE(path, "data/sodso/robotcar/2015-05-19-14-06-38/gps.txt");
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> ned;
  for (Eigen::Vector3d r; in >> r.x() >> r.y() >> r.z();) ned.push_back(r);
  ASSERT_GT(ned.size(), 8000u);
  const Trajectory t = trajectory_from_gps(ned, "robotcar");
  ASSERT_EQ(t.T_world_cam.size(), ned.size());
  for (const Eigen::Isometry3d& T : t.T_world_cam) ASSERT_TRUE(T.matrix().allFinite());
  expect_level(t);
  EXPECT_LT(max_yaw_jump(t), 15.0 * kDeg);
  // Headings follow the horizontal motion over every ~5 m (loosely: the track has jumps).
  std::vector<Eigen::Vector3d> c = t.centres();
  for (Eigen::Vector3d& p : c) p.y() = 0.0;
  int checked = 0;
  for (std::size_t i = 0, j = 0; i < c.size(); i = j) {
    for (j = i + 1; j < c.size() && (c[j] - c[i]).norm() < 5.0;) ++j;
    if (j >= c.size()) break;
    const Eigen::Vector3d motion = (c[j] - c[i]).normalized();
    EXPECT_GT(motion.dot(t.T_world_cam[i].linear().col(2)), std::cos(45 * kDeg)) << "frame " << i;
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

TEST(SimTrajectory, RoutesTooLargeForAWorldAreNamedWithTheirLargestJump) {
  std::vector<Eigen::Vector3d> route;
  for (int i = 0; i < 30; ++i) route.emplace_back(0, 0, i == 10 ? 1e6 : i);
  const std::string problem = sim::route_size_problem(route, sim::WorldConfig{});
  EXPECT_NE(problem.find("between frames 9 and 10"), std::string::npos) << problem;
  EXPECT_THROW(sim::World::build(route, sim::WorldConfig{}), std::invalid_argument);
  route[10].z() = 10;
  EXPECT_EQ(sim::route_size_problem(route, sim::WorldConfig{}), "");
  route[4].x() = std::nan("");
  EXPECT_NE(sim::route_size_problem(route, sim::WorldConfig{}).find("frame 4"), std::string::npos);
}

TEST(SimTrajectory, StereoCameraProjectRayRoundTrip) {
  StereoCamera cam;
  cam.fy = 0.9 * cam.fx;  // non-square pixels catch swapped focal lengths
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, cam.width - 1.0), v(0.0, cam.height - 1.0),
      depth(0.5, 80.0);
  Eigen::Vector2d px;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector2d pixel(u(rng), v(rng));
    const Eigen::Vector3d r = cam.ray(pixel.x(), pixel.y());
    ASSERT_NEAR(r.norm(), 1.0, 1e-12);
    ASSERT_TRUE(cam.project(r * depth(rng), px));
    ASSERT_LT((px - pixel).norm(), 1e-9);
  }
  EXPECT_TRUE(cam.project({0, 0, 10}, px));
  EXPECT_NEAR(px.x(), cam.cx, 1e-12);
  EXPECT_FALSE(cam.project({0, 0, -10}, px));   // behind
  EXPECT_FALSE(cam.project({100, 0, 10}, px));  // right of the image
  EXPECT_FALSE(cam.project({0, -50, 10}, px));  // above the image
}

}  // namespace
}  // namespace loopscan::sim
