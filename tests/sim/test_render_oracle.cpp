// The renderer's tile lists against its oracle, World::raycast for every pixel: the same depth
// and the same gray on (nearly) every pixel, across seasons, sessions, both cameras, a sloped
// street and the full KITTI resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "loopscan/sim/render_noise.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"

namespace loopscan {
namespace {

struct Agreement {
  int pixels = 0, seen = 0;         // all pixels, pixels the oracle sees a surface in
  int depth_bad = 0, gray_bad = 0;  // depth off by > 1e-3 relative (or sky vs surface), gray > 1
};

Agreement compare(const sim::World& world, const sim::Conditions& c, const sim::StereoCamera& cam,
                  const Eigen::Isometry3d& T, int camera_index, int frame) {
  sim::RenderConfig fast, oracle;
  fast.threads = oracle.threads = 2;
  oracle.raycast_every_pixel = true;
  const auto d0 = sim::render_depth(world, c, cam, T, camera_index, fast);
  const auto d1 = sim::render_depth(world, c, cam, T, camera_index, oracle);
  const auto g0 = sim::render_view(world, c, cam, T, camera_index, frame, fast);
  const auto g1 = sim::render_view(world, c, cam, T, camera_index, frame, oracle);
  Agreement a;
  for (std::size_t i = 0; i < d0.size(); ++i) {
    ++a.pixels;
    a.seen += d1[i] > 0;
    const bool same_kind = (d0[i] > 0) == (d1[i] > 0);
    a.depth_bad += !same_kind || std::abs(d0[i] - d1[i]) > 1e-3 * d1[i];
    a.gray_bad += std::abs(int(g0.pixels[i]) - int(g1.pixels[i])) > 1;
  }
  return a;
}

void expect_agreement(const Agreement& a, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_GT(a.seen, a.pixels / 2);  // mostly surfaces: the comparison is not about the sky
  EXPECT_LE(a.depth_bad, a.pixels / 1000) << a.depth_bad << " of " << a.pixels;
  EXPECT_LE(a.gray_bad, a.pixels / 100) << a.gray_bad << " of " << a.pixels;
}

TEST(RenderOracle, ShortStreetAllSeasonsBothCameras) {
  const sim::Trajectory route = sim::make_builtin_trajectory("short");
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.25);
  for (const auto season :
       {sim::Season::Spring, sim::Season::Summer, sim::Season::Fall, sim::Season::Winter}) {
    sim::Conditions c = sim::Conditions::for_season(season);
    c.session_seed = 3 + static_cast<unsigned>(season);  // other parked cars
    for (const int frame : {0, 45, 90}) {
      for (int cam_index = 0; cam_index < 2; ++cam_index) {
        expect_agreement(compare(world, c, cam, route.T_world_cam[frame], cam_index, frame),
                         sim::season_name(season) + " frame " + std::to_string(frame) + " camera " +
                             std::to_string(cam_index));
      }
    }
  }
}

TEST(RenderOracle, SlopedStreetLookingUpAndDown) {
  // A street climbing 12 m over 240 m (y down): the ground is found by iteration, not a plane.
  std::vector<Eigen::Vector3d> centreline;
  for (int i = 0; i <= 240; ++i) centreline.emplace_back(0.0, -0.05 * i, i);
  const sim::World world = sim::World::build(centreline, sim::WorldConfig{});
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.25);
  const sim::Conditions c = sim::Conditions::for_season(sim::Season::Summer);
  for (const double yaw : {0.0, M_PI, 0.4}) {  // uphill, downhill, towards the houses
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T.translation() = centreline[120];
    expect_agreement(compare(world, c, cam, T, 0, 1), "yaw " + std::to_string(yaw));
  }
}

TEST(RenderOracle, CityAtFullResolution) {
  const sim::Trajectory route = sim::make_builtin_trajectory("city");
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::StereoCamera cam;  // 1241 x 376
  const sim::Conditions c = sim::Conditions::for_season(sim::Season::Winter);
  const int frame = static_cast<int>(route.T_world_cam.size() / 3);
  expect_agreement(compare(world, c, cam, route.T_world_cam[frame], 1, frame), "city");
}

TEST(RenderOracle, OpenRoadWithMarkingsAndGuardRails) {
  const sim::Trajectory route = sim::make_builtin_trajectory("highway");
  const sim::World world = sim::World::build(route.centres(), sim::open_road_world_config());
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.5);
  const sim::Conditions c = sim::Conditions::for_season(sim::Season::Summer);
  for (const int frame : {10, 300})  // a straight, the bend
    expect_agreement(compare(world, c, cam, route.T_world_cam[frame], 0, frame),
                     "open road frame " + std::to_string(frame));
}

TEST(RenderOracle, EmptyWorldIsAllSky) {
  const sim::World empty;
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.1);
  sim::RenderConfig rc;
  const auto depth =
      sim::render_depth(empty, sim::Conditions{}, cam, Eigen::Isometry3d::Identity(), 0, rc);
  for (const double d : depth) ASSERT_EQ(d, 0.0);
}

// FNV-1a digests of views of the short street (half resolution, noise on) as the renderer drew
// them before the tile lists (one World::raycast per pixel, std::normal_distribution noise,
// commit 0226d70): the speed-ups changed no pixel. glibc's libm on x86-64.
TEST(RenderOracle, ImagesAreBitIdenticalToTheGridWalkRenderer) {
#if defined(__GLIBC__) && defined(__x86_64__)
  const sim::Trajectory route = sim::make_builtin_trajectory("short");
  const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  const sim::StereoCamera cam = sim::scaled_camera(sim::StereoCamera{}, 0.5);
  const std::uint64_t expected[2][2] = {{0x9b5bb024ba7bcc1fULL, 0xca224da87adacee7ULL},
                                        {0xe8646cfdb31c3a92ULL, 0xa5861ebcdf417b79ULL}};
  for (int s = 0; s < 2; ++s) {
    const auto c = sim::Conditions::for_season(s == 0 ? sim::Season::Summer : sim::Season::Winter);
    for (int side = 0; side < 2; ++side) {
      const auto g = sim::render_view(world, c, cam, route.T_world_cam[40], side, 40, {});
      std::uint64_t h = 0xcbf29ce484222325ULL;
      for (const std::uint8_t p : g.pixels) h = (h ^ p) * 0x100000001b3ULL;
      EXPECT_EQ(h, expected[s][side]) << "season " << s << " camera " << side;
    }
  }
#else
  GTEST_SKIP() << "digests taken with glibc on x86-64";
#endif
}

TEST(RenderOracle, SensorNoiseIsTheStandardLibrarysStream) {
  for (const unsigned seed : {0u, 1u, 5489u, 2654435761u, 4294967295u}) {
    std::mt19937 reference_rng(seed);
    sim::Mt19937 rng(seed);
    for (int i = 0; i < 2000; ++i) ASSERT_EQ(rng(), reference_rng()) << seed << " draw " << i;
  }
#if defined(__GLIBCXX__)  // the polar method and its order are libstdc++'s
  for (const unsigned seed : {1u, 77u, 3141592653u}) {
    std::mt19937 reference_rng(seed);
    std::normal_distribution<double> reference(0.0, 1.5);
    sim::GaussianNoise noise(seed, 1.5);
    for (int i = 0; i < 5000; ++i) ASSERT_EQ(noise(), reference(reference_rng)) << seed << " " << i;
  }
#endif
}

}  // namespace
}  // namespace loopscan
