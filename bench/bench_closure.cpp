// Loop closing, single thread: the place cloud and the verification of one candidate (a true
// revisit and a wrong place) on the real k06-summer fixture, the whole closer over that drive
// (stage times per keyframe), and the pose-graph solve at 1k / 5k / 20k keyframes (bytes per
// place: `close` writes them into metrics.json).
//   build/bench/loopscan_bench_closure [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <tuple>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/closure/pose_graph.hpp"
#include "loopscan/closure/verification.hpp"
#include "loopscan/config/configuration.hpp"
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

struct Fixture {  // the k06 drive as the VO exported it
  std::vector<KeyframePose> poses;
  std::vector<IdPoint> points;
};

const Fixture& fixture() {
  static const Fixture f{io::read_sodso_poses(fixture_dir() + "/poses_history_file.txt"),
                         io::read_sodso_points(fixture_dir() + "/pts_history_file.txt.gz")};
  return f;
}

struct Places {
  std::vector<int> ids;
  std::vector<closure::Points3f> voxel;  // per described keyframe
  std::vector<Eigen::Vector3d> gt;
};

const Places& places() {
  static const Places p = [] {
    Places x;
    const auto gt = io::read_kitti_poses(fixture_dir() + "/gt.txt");
    ScanImitator im;
    CameraPoints in;
    std::vector<Eigen::Vector3f> raw;
    Cloud scan;
    for_each_keyframe(fixture().poses, fixture().points,
                      [&](const KeyframePose& k, const IdPoint* pts, std::size_t n) {
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

// A drifted route of n keyframes 2 m apart turning 90 degrees every 200 m; from its second
// half, every 5th keyframe gets a loop with the true relative pose to the keyframe n/2 before
// it (a consistent constraint, not a revisit of the same street unless n/2 is a multiple of
// 400).
struct Drive {
  std::vector<Eigen::Isometry3d> gt, odometry;  // odometry[i]: T_{i-1,i} (odometry[0] unused)
  std::vector<std::tuple<int, int, Eigen::Isometry3d>> loops;  // (query, match, T_query_match)
};

Drive drifted_drive(int n) {
  Drive d;
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0, 1);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  d.odometry.push_back(Eigen::Isometry3d::Identity());
  for (int i = 0; i < n; ++i) {
    d.gt.push_back(T);
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() = Eigen::Vector3d(0, 0, 2.0);
    if ((i % (n / 2)) % 100 == 99) step.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(0, -1, 0)).toRotationMatrix();
    Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
    drift.linear() = Eigen::AngleAxisd(0.1 * M_PI / 180 * noise(rng), Eigen::Vector3d(0, -1, 0)).toRotationMatrix();
    drift.translation() = Eigen::Vector3d(noise(rng), 0, noise(rng)) * 0.02;
    d.odometry.push_back(step * drift);  // T_{i,i+1}
    T = T * step;
  }
  for (int q = n / 2; q < n; q += 5)
    d.loops.emplace_back(q, q - n / 2, d.gt[q].inverse() * d.gt[q - n / 2]);
  return d;
}

// Nodes [0, n) of the drive, from its odometry.
void add_nodes(closure::PoseGraph& g, const Drive& d, int from, int to) {
  for (int i = from; i < to; ++i) {
    if (i == 0) {
      g.add_node(Eigen::Isometry3d::Identity());
    } else {
      g.add_node(g.pose(i - 1) * d.odometry[std::size_t(i)], &d.odometry[std::size_t(i)]);
    }
  }
}

closure::PoseGraphConfig graph_config(bool incremental) {
  closure::PoseGraphConfig c;
  c.incremental = incremental;
  return c;
}

void BM_GraphSolveAllLoops(benchmark::State& state) {  // every loop at once, from the drift
  const int n = int(state.range(0));
  const Drive d = drifted_drive(n);
  closure::GraphSolve s;
  for (auto _ : state) {
    state.PauseTiming();
    closure::PoseGraph g;
    add_nodes(g, d, 0, n);
    for (const auto& [a, b, T] : d.loops) g.add_loop_unsolved(a, b, T);
    state.ResumeTiming();
    s = g.optimise();
  }
  state.counters["iterations"] = s.iterations;
  state.counters["loops"] = double(d.loops.size());
}
BENCHMARK(BM_GraphSolveAllLoops)->Arg(1000)->Arg(5000)->Arg(20000)->Unit(benchmark::kMillisecond)->Iterations(3);

// One more loop into a solved graph, timed once (a repeat of it would find the graph already
// agreeing); Arg 1: a local solve (the default), 0: the whole graph.
void BM_GraphAddLoopOnline(benchmark::State& state) {
  const int n = int(state.range(0));
  const Drive d = drifted_drive(n);
  closure::PoseGraph g(graph_config(state.range(1) == 1));
  add_nodes(g, d, 0, n);
  for (std::size_t i = 0; i + 1 < d.loops.size(); ++i) {
    const auto& [a, b, T] = d.loops[i];
    g.add_loop_unsolved(a, b, T);
  }
  g.optimise();
  const auto& [a, b, T] = d.loops.back();
  closure::GraphSolve s;
  for (auto _ : state) g.add_loop(a, b, T, &s);
  state.counters["iterations"] = s.iterations;
  state.counters["moved_nodes"] = double(s.moved_nodes);
}
BENCHMARK(BM_GraphAddLoopOnline)
    ->ArgsProduct({{1000, 5000, 20000}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The whole drive online, as the loop closer sees it: keyframes arrive, each loop is added
// (and solved) when its query keyframe arrives. Reports the time from a loop to corrected poses
// (median, 99th percentile, the first loop closing the lap, the worst) and how far the online
// estimate ends from the whole graph's solution of the same loops.
// Arg 1: 1 the default configuration, 0 without coarse solves (PoseGraphConfig::coarse_nodes 0).
void BM_GraphDriveOnline(benchmark::State& state) {
  const int n = int(state.range(0));
  const Drive d = drifted_drive(n);
  closure::PoseGraphConfig config;
  if (state.range(1) == 0) config.coarse_nodes = 0;
  std::vector<double> ms;
  double first = 0, worst_m = 0, rms_m = 0, moved = 0, online_gt = 0, whole_gt = 0;
  for (auto _ : state) {
    closure::PoseGraph g(config);
    ms.clear();
    int added = 0;
    for (const auto& [q, m, T] : d.loops) {
      add_nodes(g, d, added, q + 1);
      added = q + 1;
      const auto t0 = std::chrono::steady_clock::now();
      closure::GraphSolve s;
      g.add_loop(q, m, T, &s);
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      moved += double(s.moved_nodes);
    }
    state.PauseTiming();
    first = ms.front();
    closure::PoseGraph whole(graph_config(false));
    add_nodes(whole, d, 0, added);
    for (const auto& [q, m, T] : d.loops) whole.add_loop_unsolved(q, m, T);
    whole.optimise();
    worst_m = rms_m = online_gt = whole_gt = 0;
    for (int i = 0; i < added; ++i) {
      const double e = (g.position(i) - whole.position(i)).norm();
      worst_m = std::max(worst_m, e);
      rms_m += e * e;
      online_gt += (g.position(i) - d.gt[std::size_t(i)].translation()).squaredNorm();
      whole_gt += (whole.position(i) - d.gt[std::size_t(i)].translation()).squaredNorm();
    }
    rms_m = std::sqrt(rms_m / added);
    online_gt = std::sqrt(online_gt / added);
    whole_gt = std::sqrt(whole_gt / added);
    state.ResumeTiming();
  }
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double f) {
    return sorted[std::min(sorted.size() - 1, std::size_t(f * double(sorted.size())))];
  };
  state.counters["loops"] = double(ms.size());
  state.counters["p50_ms"] = at(0.5);
  state.counters["p99_ms"] = at(0.99);
  state.counters["first_ms"] = first;
  state.counters["max_ms"] = sorted.back();
  state.counters["moved_nodes"] = moved / double(ms.size() * state.iterations());
  state.counters["vs_whole_max_m"] = worst_m;
  state.counters["vs_whole_rms_m"] = rms_m;
  state.counters["online_error_m"] = online_gt;  // RMS against the ground truth, same frame
  state.counters["whole_error_m"] = whole_gt;
}
BENCHMARK(BM_GraphDriveOnline)
    ->ArgsProduct({{1000, 5000, 20000}, {1, 0}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The whole closer over the k06 drive with `close`'s default configuration on the argument's
// threads (the targets are one thread's): each stage's milliseconds from the closer's own stage
// clocks, the means metrics.json reports (the per-verification figure counts every verified
// candidate, accepted or not).
void BM_CloseDrive(benchmark::State& state) {
  const Fixture& f = fixture();  // read before the timing starts
  closure::LoopCloserConfig config = loop_closer_config(Configuration::defaults());
  config.threads = int(state.range(0));
  closure::StageTimes t;
  std::size_t accepted = 0;
  for (auto _ : state) {
    closure::LoopCloser closer(config);
    accepted = 0;
    for_each_keyframe(f.poses, f.points,
                      [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                        accepted += closer.add_keyframe(k, p, n).accepted.size();
                      });
    closer.finish();
    t = closer.times();
  }
  const closure::StageMeans ms = closure::stage_means(t);
  state.counters["scan_ms"] = ms.scan;
  state.counters["describe_ms"] = ms.describe;
  state.counters["query_ms"] = ms.query;
  state.counters["cloud_ms"] = ms.cloud;
  state.counters["verify_ms"] = ms.verify;
  state.counters["graph_ms"] = ms.graph;
  // Every stage's time per keyframe (metrics.json's total is the run's wall time, reading
  // included).
  state.counters["total_ms"] =
      (t.scan + t.describe + t.query + t.cloud + t.verify + t.graph) / std::max(t.keyframes, 1);
  state.counters["ms_per_verification"] = ms.per_verification;
  state.counters["verifications"] = t.verifications;
  state.counters["loops"] = double(accepted);
}
BENCHMARK(BM_CloseDrive)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace loopscan

BENCHMARK_MAIN();
