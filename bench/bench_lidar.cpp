// A real KITTI Velodyne scan (~120k points) as a place: read, crop + filter, Scan Context
// (paper parameters and Scan Context's own), single thread.
//   build/bench/loopscan_bench_lidar
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/lidar_scan.hpp"
#include "loopscan/io/lidar_file.hpp"

namespace loopscan {
namespace {

std::string scan_file() {
  const char* env = std::getenv("LOOPSCAN_SHARED");
  return std::string(env ? env : LOOPSCAN_SHARED_DIR) + "/data/lidar/kitti00_000094.bin";
}

const Cloud& lidar() {
  static const Cloud c = io::read_lidar_scan(scan_file());
  return c;
}

// Arg: 0 = the paper's parameters (45 m, height range), 1 = Scan Context's (80 m, max height).
SequenceOptions options(bool original) {
  SequenceOptions o =
      SequenceOptions::make(Method::ScanContext, Mode::Default, original ? 80.0 : 45.0);
  o.descriptors.scan_context.max_height = original;
  return o;
}

void BM_LidarRead(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(io::read_lidar_scan(scan_file()));
}
BENCHMARK(BM_LidarRead)->Unit(benchmark::kMillisecond);

void BM_LidarCropFilter(benchmark::State& state) {
  const SequenceOptions o = options(state.range(0) == 1);
  for (auto _ : state)
    benchmark::DoNotOptimize(lidar_scan_as_imitated(lidar(), ScanFilter::Cartesian, o.imitation));
}
BENCHMARK(BM_LidarCropFilter)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Crop + filter + Scan Context with its lateral versions: the whole "describe one scan".
void BM_LidarScanContext(benchmark::State& state) {
  const SequenceOptions o = options(state.range(0) == 1);
  for (auto _ : state) {
    const Cloud scan = lidar_scan_as_imitated(lidar(), ScanFilter::Cartesian, o.imitation);
    benchmark::DoNotOptimize(describe(Method::ScanContext, scan, o.descriptors));
  }
  state.counters["points"] = static_cast<double>(lidar().size());
}
BENCHMARK(BM_LidarScanContext)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace loopscan

int main(int argc, char** argv) {
  if (!std::filesystem::exists(loopscan::scan_file())) {
    std::fprintf(stderr, "loopscan_bench_lidar: %s not found (set LOOPSCAN_SHARED)\n",
                 loopscan::scan_file().c_str());
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
