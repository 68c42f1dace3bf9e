// Loop closing, single thread: the place cloud and the verification of one candidate (a true
// revisit and a wrong place) on the real k06-summer fixture, and the pose-graph solve at 1k /
// 5k / 20k keyframes (bytes per place: `close` writes them into metrics.json).
//   build/bench/loopscan_bench_closure [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>

#include "loopscan/closure/pose_graph.hpp"
#include "loopscan/closure/verification.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/sodso.hpp"

namespace loopscan {
namespace {

std::string fixture_dir() {
  const char* env = std::getenv("LOOPSCAN_SHARED");
  return std::string(env ? env : LOOPSCAN_SHARED_DIR) + "/fixtures/k06-summer";
}

struct Places {
  std::vector<int> ids;
  std::vector<closure::Points3f> voxel;  // per described keyframe
  std::vector<Eigen::Vector3d> gt;
};

const Places& places() {
  static const Places p = [] {
    Places x;
    const auto poses = io::read_sodso_poses(fixture_dir() + "/poses_history_file.txt");
    const auto points = io::read_sodso_points(fixture_dir() + "/pts_history_file.txt.gz");
    const auto gt = io::read_kitti_poses(fixture_dir() + "/gt.txt");
    ScanImitator im;
    CameraPoints in;
    std::vector<Eigen::Vector3f> raw;
    Cloud scan;
    for_each_keyframe(poses, points, [&](const KeyframePose& k, const IdPoint* pts, std::size_t n) {
      if (!im.next_scan(k, pts, n, false, ScanFilter::Cartesian, scan)) return;
      im.last_in_range(raw);
      x.ids.push_back(k.id);
      x.voxel.push_back(closure::voxel_cloud(raw));
      x.gt.push_back(gt[std::size_t(k.id)].col(3));
    });
    return x;
  }();
  return p;
}

// A revisit (second pass, within 2 m, far apart in time) and a wrong place (over 100 m away).
std::pair<std::size_t, std::size_t> pair_of(bool revisit) {
  const Places& p = places();
  for (std::size_t q = p.ids.size() * 3 / 4; q < p.ids.size(); ++q) {
    for (std::size_t m = 0; m + 300 < q; ++m) {
      const double d = (p.gt[q] - p.gt[m]).norm();
      if (revisit ? d < 2.0 : d > 100.0) return {q, m};
    }
  }
  return {0, 0};
}

void BM_PlaceCloud(benchmark::State& state) {  // voxel cloud -> index, lazy normals, place cloud
  const Places& p = places();
  std::size_t i = 0;
  for (auto _ : state) {
    const closure::TargetCloud target(p.voxel[i % p.voxel.size()]);
    benchmark::DoNotOptimize(closure::to_place_cloud(target));
    ++i;
  }
  state.counters["points"] = double(p.voxel[0].size());
}
BENCHMARK(BM_PlaceCloud)->Unit(benchmark::kMillisecond);

void report(benchmark::State& state, const closure::Loop& loop, const char* label) {
  state.SetLabel(label);
  state.counters["overlap"] = loop.overlap;
  state.counters["accepted"] = loop.accepted();
  state.counters["iterations"] = loop.iterations;
}

void BM_Verify(benchmark::State& state) {
  const auto [q, m] = pair_of(state.range(0) == 1);
  const Places& p = places();
  const closure::PlaceCloud place = closure::to_place_cloud(closure::TargetCloud(p.voxel[m]));
  closure::Loop loop;
  for (auto _ : state) {
    const closure::TargetCloud target(p.voxel[q]);  // normals fitted afresh each time
    loop = closure::verify_candidate(target, place, {closure::yaw_rotation(0.0), closure::yaw_rotation(M_PI)});
    benchmark::DoNotOptimize(loop);
  }
  report(state, loop, state.range(0) == 1 ? "revisit" : "wrong place");
}
BENCHMARK(BM_Verify)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// A nearby place (the revisit, its predicted pose 5 m off along the track): ICP starts from
// the bird's-eye search (Arg 1) or from the prediction shifted along the track (Arg 0).
void BM_VerifyNearby(benchmark::State& state) {
  const auto [q, m] = pair_of(true);
  const Places& p = places();
  const closure::PlaceCloud place = closure::to_place_cloud(closure::TargetCloud(p.voxel[m]));
  Eigen::Isometry3d predicted = Eigen::Isometry3d::Identity();
  predicted.translation().z() = 5.0;
  std::optional<closure::BirdsEyeGrid> grid;  // the closer builds it with the query's place cloud
  if (state.range(0) == 1) grid.emplace(closure::to_place_cloud(closure::TargetCloud(p.voxel[q])));
  closure::Loop loop;
  for (auto _ : state) {
    const closure::TargetCloud target(p.voxel[q]);
    loop = closure::verify_candidate(target, place, {predicted}, {}, grid ? &*grid : nullptr);
    benchmark::DoNotOptimize(loop);
  }
  report(state, loop, state.range(0) == 1 ? "bird's-eye starts" : "along-track starts");
}
BENCHMARK(BM_VerifyNearby)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_BirdsEyeSearch(benchmark::State& state) {  // one guess, the default window
  const auto [q, m] = pair_of(true);
  const Places& p = places();
  const closure::PlaceCloud place = closure::to_place_cloud(closure::TargetCloud(p.voxel[m]));
  const closure::BirdsEyeGrid grid(closure::to_place_cloud(closure::TargetCloud(p.voxel[q])));
  for (auto _ : state) {
    benchmark::DoNotOptimize(closure::birds_eye_search(grid, place, {Eigen::Isometry3d::Identity()}));
  }
}
BENCHMARK(BM_BirdsEyeSearch)->Unit(benchmark::kMillisecond);

// A drifted route of n keyframes 2 m apart around blocks of 200 m, driven twice; loops join
// the second lap to the first every 5 keyframes.
struct Graph {
  closure::PoseGraph graph;
  std::vector<std::tuple<int, int, Eigen::Isometry3d>> loops;
};

Graph drifted_graph(int n) {
  Graph g;
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0, 1);
  std::vector<Eigen::Isometry3d> gt;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity(), vo = T;
  for (int i = 0; i < n; ++i) {
    gt.push_back(T);
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = Eigen::Vector3d(0, 0, 2.0);
    if ((i % (n / 2)) % 100 == 99) step.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(0, -1, 0)).toRotationMatrix();
    Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
    drift.linear() = Eigen::AngleAxisd(0.1 * M_PI / 180 * noise(rng), Eigen::Vector3d(0, -1, 0)).toRotationMatrix();
    drift.translation() = Eigen::Vector3d(noise(rng), 0, noise(rng)) * 0.02;
    const Eigen::Isometry3d odo = step * drift;
    if (i == 0) {
      g.graph.add_node(vo);
    } else {
      vo = vo * odo;
      g.graph.add_node(vo, &odo);
    }
    T = T * step;
  }
  for (int q = n / 2; q < n; q += 5) g.loops.emplace_back(q, q - n / 2, gt[q].inverse() * gt[q - n / 2]);
  return g;
}

void BM_GraphSolveAllLoops(benchmark::State& state) {  // every loop at once, from the drift
  const int n = int(state.range(0));
  closure::GraphSolve s;
  for (auto _ : state) {
    state.PauseTiming();
    Graph g = drifted_graph(n);
    for (const auto& [a, b, T] : g.loops) g.graph.add_loop_unsolved(a, b, T);
    state.ResumeTiming();
    s = g.graph.optimise();
  }
  state.counters["iterations"] = s.iterations;
  state.counters["loops"] = double(n / 10);
}
BENCHMARK(BM_GraphSolveAllLoops)->Arg(1000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_GraphAddLoopOnline(benchmark::State& state) {  // one more loop into a solved graph
  const int n = int(state.range(0));
  Graph g = drifted_graph(n);
  for (std::size_t i = 0; i + 1 < g.loops.size(); ++i) {
    const auto& [a, b, T] = g.loops[i];
    g.graph.add_loop_unsolved(a, b, T);
  }
  g.graph.optimise();
  const auto& [a, b, T] = g.loops.back();
  for (auto _ : state) {  // (each iteration adds the loop once more: harmless duplicates)
    closure::GraphSolve s;
    g.graph.add_loop(a, b, T, &s);
    state.counters["iterations"] = s.iterations;
  }
}
BENCHMARK(BM_GraphAddLoopOnline)->Arg(1000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace loopscan

BENCHMARK_MAIN();
