// The renderer's ground caches against their oracle, CentrelineIndex::nearest for every query:
// the tree search and the anchored candidate lists give the same nearest segment, and views of
// sloped routes (a winding hill road driven twice, KITTI 00) are bit for bit the oracle's.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/sim/render_ground.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

// A winding road climbing and falling, driven one and a half times round (a revisit, so two
// passes of the centreline lie side by side).
std::vector<Eigen::Vector3d> hill_loop() {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i <= 900; ++i) {
    const double a = i * 0.0105;  // ~1 m steps on a ~95 m radius
    const double r = 95.0 + 12.0 * std::sin(3.0 * a);
    c.emplace_back(r * std::cos(a), -6.0 * std::sin(2.0 * a) - 0.002 * i, r * std::sin(a));
  }
  return c;
}

void expect_same_views(const sim::World& world, const sim::StereoCamera& cam,
                       const Eigen::Isometry3d& T, int frame, const std::string& what) {
  SCOPED_TRACE(what);
  sim::RenderConfig fast, oracle;
  oracle.exact_ground = true;
  const auto c = sim::Conditions::for_season(sim::Season::Fall);
  for (int side = 0; side < 2; ++side) {
    EXPECT_EQ(sim::render_view(world, c, cam, T, side, frame, fast).pixels,
              sim::render_view(world, c, cam, T, side, frame, oracle).pixels);
    EXPECT_EQ(sim::render_depth(world, c, cam, T, side, fast),
              sim::render_depth(world, c, cam, T, side, oracle));
  }
}

TEST(RenderGround, CachedNearestIsTheIndexNearest) {
  const auto path = hill_loop();
  const sim::CentrelineIndex index(path, 10.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> start(-200.0, 200.0), step(-1.0, 1.0);
  sim::NearestCache cache(index);
  int checked = 0;
  for (int walk = 0; walk < 40; ++walk) {
    double x = start(rng), z = start(rng);
    // Slow and fast walks: the anchored lists and the tree search.
    const double speed = walk % 2 == 0 ? 0.05 : 3.0 * (1 + walk % 5);
    for (int i = 0; i < 300; ++i, ++checked) {
      x += speed * step(rng);
      z += speed * step(rng);
      const auto want = index.nearest(x, z), got = cache.at(x, z);
      const auto tree = index.nearest_from(static_cast<std::uint32_t>(i), x, z);
      ASSERT_TRUE(got.found);
      ASSERT_EQ(got.distance, want.distance) << x << ", " << z;
      ASSERT_EQ(got.y, want.y) << x << ", " << z;
      ASSERT_EQ(tree.distance, want.distance) << x << ", " << z;
      ASSERT_EQ(tree.y, want.y) << x << ", " << z;
    }
  }
  EXPECT_EQ(checked, 12000);
}

TEST(RenderGround, HillLoopViewsAreTheOracles) {
  const auto path = hill_loop();
  const sim::World world = sim::World::build(path, sim::WorldConfig{});
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.5);
  for (const int i : {30, 250, 480, 700}) {
    const Eigen::Vector3d ahead = path[i + 5] - path[i];
    // Looking along the road, slightly down the slope or up it.
    Eigen::Isometry3d T = sim::level_pose(path[i], std::atan2(ahead.x(), ahead.z()));
    expect_same_views(world, cam, T, i, "frame " + std::to_string(i));
  }
}

TEST(RenderGround, Kitti00ViewsAreTheOracles) {
  const std::string path = test::shared_dir() + "/data/kitti/poses/00.txt";
  LOOPSCAN_SKIP_WITHOUT_SHARED(std::filesystem::exists(path), path);
  const sim::Trajectory route = sim::trajectory_from_kitti(io::read_kitti_poses(path), path);
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.5);
  for (const int frame : {378, 1892, 3405})
    expect_same_views(world, cam, route.T_world_cam[frame], frame,
                      "frame " + std::to_string(frame));
}

}  // namespace
}  // namespace loopscan
