#include "lidar_describe.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

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
  SequenceSignatures result;
  double read_ms = 0, imitate_ms = 0, describe_ms = 0, points = 0, kept = 0;
  std::size_t skipped = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    auto t0 = std::chrono::steady_clock::now();
    io::LidarReadStats stats;
    const Cloud lidar = io::read_lidar_scan(files[i], &stats);
    read_ms += ms_since(t0);
    skipped += stats.non_finite_skipped;
    t0 = std::chrono::steady_clock::now();
    const Cloud scan = lidar_scan_as_imitated(lidar, filter_for(method), options.imitation);
    imitate_ms += ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    Eigen::Matrix3d frame;
    result.signatures.push_back(describe(method, scan, options.descriptors, &frame));
    describe_ms += ms_since(t0);
    result.frames.push_back(frame);
    result.keyframe_ids.push_back(static_cast<int>(i));
    points += static_cast<double>(lidar.size());
    kept += static_cast<double>(scan.size());
  }
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
