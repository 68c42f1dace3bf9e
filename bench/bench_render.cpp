// The stereo renderer at KITTI resolution (1241x376) on the built-in city, summer: stereo pairs
// per second on 1 and 2 threads (Arg = threads), and its stages on one thread, per view:
// visibility only (render_depth: tile lists + ray tests), + shading (no sensor noise), and the
// per-pixel oracle (World::raycast, what the renderer did before); and a sloped route, KITTI 00's
// ground truth (LOOPSCAN_KITTI_POSES, default ../shared/data/kitti/poses/00.txt). On demand.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"

namespace {

using namespace loopscan;

struct Scene {
  sim::Trajectory route = sim::make_builtin_trajectory("city");
  sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
  sim::Conditions conditions = sim::Conditions::for_season(sim::Season::Summer);
  sim::StereoCamera camera;
};

const Scene& scene() {
  static const Scene s;
  return s;
}

// 24 frames spread over the route: straights, turns, open and dense streets.
int frame_of(int i) {
  const int n = static_cast<int>(scene().route.T_world_cam.size());
  return static_cast<int>((static_cast<long>(i % 24) * 2 + 1) * n / 48);
}

void BM_RenderStereoPair(benchmark::State& state) {
  const Scene& s = scene();
  sim::RenderConfig rc;
  rc.threads = static_cast<int>(state.range(0));
  int i = 0;
  for (auto _ : state) {
    const int frame = frame_of(i++);
    for (int side = 0; side < 2; ++side)
      benchmark::DoNotOptimize(sim::render_view(s.world, s.conditions, s.camera,
                                                s.route.T_world_cam[frame], side, frame, rc));
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderStereoPair)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg 0: visibility only; 1: + shading, no noise; 2: the whole view; 3: the oracle.
void BM_RenderViewStage(benchmark::State& state) {
  const Scene& s = scene();
  sim::RenderConfig rc;
  rc.noise_sigma = state.range(0) == 1 ? 0.0 : rc.noise_sigma;
  rc.raycast_every_pixel = state.range(0) == 3;
  int i = 0;
  for (auto _ : state) {
    const int frame = frame_of(i++);
    const auto& T = s.route.T_world_cam[frame];
    if (state.range(0) == 0)
      benchmark::DoNotOptimize(sim::render_depth(s.world, s.conditions, s.camera, T, 0, rc));
    else
      benchmark::DoNotOptimize(sim::render_view(s.world, s.conditions, s.camera, T, 0, frame, rc));
  }
}
BENCHMARK(BM_RenderViewStage)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// A sloped street network (KITTI 00's poses: the ground is found by iteration): 12 frames spread
// over the route, one stereo pair per iteration, 12 iterations (the same frames in every
// repetition; Arg = threads).
struct KittiScene {
  sim::Trajectory route;
  sim::World world;
  sim::Conditions conditions = sim::Conditions::for_season(sim::Season::Summer);
  sim::StereoCamera camera;
  KittiScene() {
    const char* env = std::getenv("LOOPSCAN_KITTI_POSES");
    const std::string path = env ? env : "../shared/data/kitti/poses/00.txt";
    if (!std::filesystem::exists(path)) return;
    route = sim::trajectory_from_kitti(io::read_kitti_poses(path), path);
    world = sim::World::build(route.centres(), sim::WorldConfig{});
  }
};

void BM_RenderKittiPair(benchmark::State& state) {
  static const KittiScene s;
  if (s.route.T_world_cam.empty()) {
    state.SkipWithError("no KITTI poses (set LOOPSCAN_KITTI_POSES)");
    return;
  }
  sim::RenderConfig rc;
  rc.threads = static_cast<int>(state.range(0));
  const int n = static_cast<int>(s.route.T_world_cam.size());
  int i = 0;
  for (auto _ : state) {
    const int frame = static_cast<int>((static_cast<long>(i++ % 12) * 2 + 1) * n / 24);
    for (int side = 0; side < 2; ++side)
      benchmark::DoNotOptimize(sim::render_view(s.world, s.conditions, s.camera,
                                                s.route.T_world_cam[frame], side, frame, rc));
  }
}
BENCHMARK(BM_RenderKittiPair)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(12)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
