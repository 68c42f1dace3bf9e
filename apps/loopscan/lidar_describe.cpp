#include "lidar_describe.hpp"

#include <algorithm>
#include <cstdio>
#include <exception>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "loopscan/core/parallel.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/lidar_scan.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/lidar_file.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "signature_outputs.hpp"

namespace loopscan::cli {

void run_lidar_describe(const LidarDescribeArgs& a) {
  const Method method = parse_method(a.method);
  const Mode mode = parse_mode(a.mode);
  if (a.params != "paper" && a.params != "scan-context")
    throw std::invalid_argument("--lidar-params: expected paper or scan-context, got '" + a.params +
                                "'");
  const bool original = a.params == "scan-context";
  const double range = a.range_m > 0 ? a.range_m : original ? 80.0 : 45.0;
  SequenceOptions options = SequenceOptions::make(method, mode, range);
  options.descriptors.scan_context.max_height = original;
  const std::vector<std::string> files = io::lidar_scan_files(a.scans);
  // Scans are independent: read and described on a.threads threads (each file by one thread,
  // so the signatures do not depend on the thread count); times are summed CPU milliseconds.
  const std::size_t n_files = files.size();
  SequenceSignatures result;
  result.signatures.resize(n_files);
  result.frames.resize(n_files);
  for (std::size_t i = 0; i < n_files; ++i) result.keyframe_ids.push_back(static_cast<int>(i));
  struct Tally {
    double read_ms = 0, imitate_ms = 0, describe_ms = 0, points = 0, kept = 0;
    std::size_t skipped = 0;
  };
  const int threads = std::max(1, std::min<int>(a.threads, static_cast<int>(n_files)));
  std::vector<Tally> tally(static_cast<std::size_t>(threads));
  std::vector<std::exception_ptr> failed(n_files);
  run_on_threads(threads, [&](int t) {
    Tally& y = tally[static_cast<std::size_t>(t)];
    for (std::size_t i = static_cast<std::size_t>(t); i < n_files; i += threads) {
      try {
        auto t0 = StageClock::now();
        io::LidarReadStats stats;
        const Cloud lidar = io::read_lidar_scan(files[i], &stats);
        y.read_ms += ms_since(t0);
        y.skipped += stats.non_finite_skipped;
        t0 = StageClock::now();
        const Cloud scan = lidar_scan_as_imitated(lidar, filter_for(method), options.imitation);
        y.imitate_ms += ms_since(t0);
        t0 = StageClock::now();
        result.signatures[i] = describe(method, scan, options.descriptors, &result.frames[i]);
        y.describe_ms += ms_since(t0);
        y.points += static_cast<double>(lidar.size());
        y.kept += static_cast<double>(scan.size());
      } catch (...) {
        failed[i] = std::current_exception();  // thrown below, the first file's first
      }
    }
  });
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
  Tally all;
  for (const Tally& y : tally) {
    all.read_ms += y.read_ms, all.imitate_ms += y.imitate_ms, all.describe_ms += y.describe_ms;
    all.points += y.points, all.kept += y.kept, all.skipped += y.skipped;
  }
  const double read_ms = all.read_ms, imitate_ms = all.imitate_ms, describe_ms = all.describe_ms,
               points = all.points, kept = all.kept;
  const std::size_t skipped = all.skipped;
  write_signatures(a.out, result, method);
  std::string list;
  for (const std::string& f : files) list += f + "\n";
  io::write_file_atomic(a.out + "/scans.txt", list);
  const double n = static_cast<double>(files.size());
  const nlohmann::json timing = {{"method", method_name(method)},
                                 {"mode", mode_name(mode)},
                                 {"input", "lidar"},
                                 {"lidar_params", a.params},
                                 {"range_m", range},
                                 {"threads", threads},
                                 {"max_height", original},
                                 {"n_signatures", files.size()},
                                 {"read_ms", read_ms / n},
                                 {"imitate_ms", imitate_ms / n},
                                 {"describe_ms", describe_ms / n},
                                 {"mean_points", points / n},
                                 {"mean_points_filtered", kept / n},
                                 {"points_non_finite_skipped", skipped}};
  io::write_file_atomic(a.out + "/timing.json", timing.dump(1) + "\n");
  std::printf(
      "%s (%s, %s parameters): %zu LiDAR scans, %.0f points each (%.0f after the filter); "
      "%.3f ms read, %.3f ms crop + filter, %.3f ms describe per scan -> %s\n",
      method_name(method).c_str(), mode_name(mode).c_str(), a.params.c_str(), files.size(),
      points / n, kept / n, read_ms / n, imitate_ms / n, describe_ms / n, shown(a.out).c_str());
}

}  // namespace loopscan::cli
