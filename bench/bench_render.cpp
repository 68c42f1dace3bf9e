// The stereo renderer at KITTI resolution (1241x376) on the built-in city, summer: stereo pairs
// per second on 1 and 2 threads (Arg = threads). On demand.
#include <benchmark/benchmark.h>

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

void BM_RenderStereoPair(benchmark::State& state) {
  const Scene& s = scene();
  sim::RenderConfig rc;
  rc.threads = static_cast<int>(state.range(0));
  int i = 0;
  for (auto _ : state) {
    // 24 frames spread over the route: straights, turns, open and dense streets.
    const int n = static_cast<int>(s.route.T_world_cam.size());
    const int frame = static_cast<int>((static_cast<long>(i++ % 24) * 2 + 1) * n / 48);
    for (int side = 0; side < 2; ++side)
      benchmark::DoNotOptimize(sim::render_view(s.world, s.conditions, s.camera,
                                                s.route.T_world_cam[frame], side, frame, rc));
  }
  state.counters["pairs_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderStereoPair)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
