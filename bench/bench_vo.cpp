// The stereo VO on real KITTI frames (`../shared/data/real/kitti06-000000-000050`, 51 pairs of
// 1226x370; LOOPSCAN_SHARED overrides the shared folder). Skipped, with the reason, when the
// frames are absent. On demand.
//   BM_VoRealFrames: the VO alone on the pairs read beforehand; process CPU time per frame and
//     ms per stage (counters), the cost on whatever threads the VO uses.
//   BM_VoRealFramesTrackingThread: the same, CPU time of the calling thread only.
//   BM_VoRealSequence: run_stereo_vo from disk, the PNGs read on the second thread as `loopscan
//     vo` does; wall time, frames per second.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>

#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/vo/image_file.hpp"
#include "loopscan/vo/run_sequence.hpp"

namespace {

using namespace loopscan;

std::string real_kitti06() {
  const char* env = std::getenv("LOOPSCAN_SHARED");
  return std::string(env ? env : LOOPSCAN_SHARED_DIR) + "/data/real/kitti06-000000-000050";
}

bool have_frames(benchmark::State& state) {
  if (std::filesystem::exists(real_kitti06() + "/calib.txt")) return true;
  state.SkipWithError(("needs " + real_kitti06() + " (../shared, or set LOOPSCAN_SHARED)").c_str());
  return false;
}

struct Pairs {
  io::KittiSequence sequence;
  vo::StereoIntrinsics camera;
  std::vector<cv::Mat> left, right;
};

const Pairs& pairs() {
  static const Pairs p = [] {
    Pairs out;
    out.sequence = io::open_kitti_sequence(real_kitti06());
    out.camera = vo::intrinsics_of(out.sequence);
    for (std::size_t i = 0; i < out.sequence.frames(); ++i) {
      out.left.push_back(vo::read_gray_image(out.sequence.left(i)));
      out.right.push_back(vo::read_gray_image(out.sequence.right(i)));
    }
    return out;
  }();
  return p;
}

void stage_counters(benchmark::State& state, const vo::StageTimes& s, double frames) {
  const auto avg = benchmark::Counter::kAvgIterations;
  state.counters["track_ms"] += benchmark::Counter(s.track / frames, avg);
  state.counters["pose_ms"] += benchmark::Counter(s.pose / frames, avg);
  state.counters["keyframe_ms"] += benchmark::Counter(s.keyframe / frames, avg);
  state.counters["ba_ms"] += benchmark::Counter(s.bundle_adjustment / frames, avg);
  state.counters["points_ms"] += benchmark::Counter(s.export_points / frames, avg);
}

void BM_VoRealFrames(benchmark::State& state) {
  if (!have_frames(state)) return;
  const Pairs& p = pairs();  // read before the timing starts
  const double n = static_cast<double>(p.left.size());
  for (auto _ : state) {
    vo::VoConfig config;
    config.ba_on_worker = state.range(0) == 1;
    vo::StereoVo odometry(p.camera, config);
    for (std::size_t i = 0; i < p.left.size(); ++i)
      benchmark::DoNotOptimize(odometry.process(static_cast<int>(i), p.left[i], p.right[i]));
    odometry.finish();
    stage_counters(state, odometry.stage_times(), n);
  }
  state.counters["ms_per_frame"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * n,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::OneK::kIs1000);
}
// Arg: VoConfig::ba_on_worker (1, the default; 0 applies each adjustment at once).
BENCHMARK(BM_VoRealFrames)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
// CPU time of the calling (tracking) thread only: the work the workers do not take off it.
BENCHMARK(BM_VoRealFrames)
    ->Name("BM_VoRealFramesTrackingThread")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond);

void BM_VoRealSequence(benchmark::State& state) {
  if (!have_frames(state)) return;
  const io::KittiSequence& s = pairs().sequence;
  for (auto _ : state) {
    const vo::SequenceRun run = vo::run_stereo_vo(s);
    benchmark::DoNotOptimize(run.trajectory.data());
    state.counters["fps"] += benchmark::Counter(run.fps, benchmark::Counter::kAvgIterations);
  }
}
BENCHMARK(BM_VoRealSequence)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
