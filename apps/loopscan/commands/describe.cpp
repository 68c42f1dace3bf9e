// loopscan describe: places from a VO export (imitated LiDAR scans), real LiDAR scans or keyframe
// images -> signatures.txt, incoming_id_file.txt, frames.txt, config.yaml, timing.json
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/lidar_scan.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/lidar_file.hpp"
#include "loopscan/io/sodso.hpp"
#include "outputs/images.hpp"
#include "outputs/signatures.hpp"

namespace loopscan::cli {
namespace {

// `describe --lidar`: real LiDAR scans (KITTI .bin[.gz], PCD, PLY), one place per scan, cropped
// and filtered like imitated scans, written like any described sequence.
void run_lidar_describe(const std::vector<std::string>& scans, const std::string& out,
                        int threads_wanted, const Configuration& c) {
  const Method method = c.method;
  const SequenceOptions options = sequence_options(c);
  const std::vector<std::string> files = io::lidar_scan_files(scans);
  // Scans are independent: read and described on several threads (each file by one thread,
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
  const int threads = std::max(1, std::min<int>(threads_wanted, static_cast<int>(n_files)));
  std::vector<Tally> tally(static_cast<std::size_t>(threads));
  std::vector<std::exception_ptr> failed(n_files);
  run_on_threads(threads, [&](int t) {
    Tally& y = tally[static_cast<std::size_t>(t)];
    for (std::size_t i = static_cast<std::size_t>(t); i < n_files; i += threads) {
      try {
        io::LidarReadStats stats;
        Cloud lidar, scan;
        {
          const ScopedTimer timer(y.read_ms);
          lidar = io::read_lidar_scan(files[i], &stats);
        }
        y.skipped += stats.non_finite_skipped;
        {
          const ScopedTimer timer(y.imitate_ms);
          scan = lidar_scan_as_imitated(lidar, filter_for(method), options.imitation, c.lidar);
        }
        {
          const ScopedTimer timer(y.describe_ms);
          result.signatures[i] = describe(method, scan, options.descriptors, &result.frames[i]);
        }
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
  write_signatures(out, result, c);
  std::string list;
  for (const std::string& f : files) list += f + "\n";
  io::write_file_atomic(out + "/scans.txt", list);
  const double n = static_cast<double>(files.size());
  const nlohmann::json timing = {
      {"method", method_name(method)},
      {"mode", mode_name(c.mode)},
      {"input", "lidar"},
      {"frame", descriptor_frame_name(descriptor_frame(method, options.descriptors))},
      {"range_m", options.imitation.range_m},
      {"threads", threads},
      {"max_height", options.descriptors.scan_context.max_height},
      {"n_signatures", files.size()},
      {"read_ms", all.read_ms / n},
      {"imitate_ms", all.imitate_ms / n},
      {"describe_ms", all.describe_ms / n},
      {"mean_points", all.points / n},
      {"mean_points_filtered", all.kept / n},
      {"points_non_finite_skipped", all.skipped}};
  io::write_file_atomic(out + "/timing.json", timing.dump(1) + "\n");
  std::printf(
      "%s (%s): %zu LiDAR scans, %.0f points each (%.0f after the filter); %.3f ms read, %.3f ms "
      "crop + filter, %.3f ms describe per scan -> %s\n",
      method_name(method).c_str(), mode_name(c.mode).c_str(), files.size(), all.points / n,
      all.kept / n, all.read_ms / n, all.imitate_ms / n, all.describe_ms / n, shown(out).c_str());
}

// The three inputs `describe` takes; exactly one of them.
struct DescribeArgs {
  ConfigFlags config;
  std::string poses, points, reset_ids;  // a VO export (SO-DSO history files)
  std::vector<std::string> lidar;        // real LiDAR scans
  ImageDescribeArgs images;              // images (gist, bow): --kitti, --keyframes, --vocab
  std::string out;
  int threads = 1;
};

void refuse_mixed_inputs(const DescribeArgs& a, bool images) {
  const bool vo = !a.poses.empty() || !a.points.empty() || !a.reset_ids.empty();
  const bool lidar = !a.lidar.empty();
  const bool image_inputs =
      !a.images.kitti.empty() || !a.images.keyframes.empty() || !a.images.vocab.empty();
  if (images) {
    if (vo || lidar)
      throw std::invalid_argument(
          "--method gist | bow describes images: --kitti, --keyframes "
          "(and --vocab), not --poses, --points, --reset-ids or --lidar");
    return;
  }
  if (image_inputs)
    throw std::invalid_argument(
        "--kitti, --keyframes and --vocab are the image baselines' "
        "inputs (--method gist | bow)");
  if (vo && lidar)
    throw std::invalid_argument(
        "give a VO export (--poses, --points) or LiDAR scans (--lidar), "
        "not both");
  if (!lidar && (a.poses.empty() || a.points.empty()))
    throw std::invalid_argument("--method " + a.config.method +
                                " needs --poses and --points (a VO export) or --lidar SCANS");
}

void run_describe(const DescribeArgs& a) {
  const Configuration c = resolve_configuration(a.config);
  const std::string method_text = method_name(c);
  refuse_mixed_inputs(a, c.image_baseline.has_value());
  if (c.image_baseline) {
    ImageDescribeArgs images = a.images;
    images.out = a.out;
    images.threads = std::max(1, a.threads);
    run_image_describe(images, c);
    return;
  }
  if (!a.lidar.empty()) {
    run_lidar_describe(a.lidar, a.out, std::max(1, a.threads), c);
    return;
  }
  const Method method = c.method;
  const std::vector<KeyframePose> poses = io::read_sodso_poses(a.poses);
  io::PointReadStats stats;
  const std::vector<IdPoint> points = io::read_sodso_points(a.points, &stats);
  if (stats.non_finite_skipped > 0) {
    std::fprintf(stderr, "warning: %s: skipped %zu points with NaN/inf values\n", a.points.c_str(),
                 stats.non_finite_skipped);
  }
  if (stats.intensity_clamped > 0) {
    std::fprintf(stderr, "warning: %s: clamped %zu intensities to [0, 255]\n", a.points.c_str(),
                 stats.intensity_clamped);
  }

  SequenceOptions options = sequence_options(c);
  options.threads = std::max(1, a.threads);
  if (c.mode == Mode::Default) {
    options.reset_ids = a.reset_ids.empty() ? detect_vo_resets(poses, c.reset_jump_m)
                                            : io::read_incoming_ids(a.reset_ids);
  } else if (!a.reset_ids.empty()) {
    throw std::invalid_argument(
        "--reset-ids: reference mode detects resets as the paper's code does");
  }
  StepProgress progress("describe " + method_text, "keyframes");
  options.progress = progress.callback();
  const SequenceSignatures result = describe_sequence(poses, points, options);
  progress.finish(", " + std::to_string(result.signatures.size()) + " signatures");
  if (result.signatures.empty()) {
    std::fprintf(stderr,
                 "warning: no signatures: %zu keyframes, but the first %d after each VO reset "
                 "only accumulate points\n",
                 poses.size(), options.imitation.init_frames);
  }

  write_signatures(a.out, result, c);
  nlohmann::json timing = {
      {"method", method_text},
      {"mode", mode_name(c.mode)},
      {"range_m", options.imitation.range_m},
      {"lookahead_m", options.imitation.lookahead_m},
      {"frame", descriptor_frame_name(descriptor_frame(method, options.descriptors))},
      {"filter", filter_for(method) == ScanFilter::Cartesian ? "cartesian" : "polar"},
      {"n_keyframes", poses.size()},
      {"n_signatures", result.signatures.size()},
      {"reset_ids", options.reset_ids},
      {"imitate_ms", result.imitate_ms},
      {"describe_ms", result.describe_ms},
      {"threads", options.threads},
      {"mean_points_in_range", result.mean_in_range},
      {"mean_points_filtered", result.mean_filtered},
      {"points_non_finite_skipped", stats.non_finite_skipped},
      {"points_intensity_clamped", stats.intensity_clamped}};
  if (method == Method::ScanContext) {  // the other methods describe each place once
    timing["lateral_versions_m"] = options.descriptors.scan_context.lateral_versions_m;
  }
  io::write_file_atomic(a.out + "/timing.json", timing.dump(1) + "\n");
  std::printf(
      "%s (%s): %zu signatures from %zu keyframes; %.3f ms imitate + %.3f ms describe "
      "per keyframe -> %s\n",
      method_text.c_str(), mode_name(c.mode).c_str(), result.signatures.size(), poses.size(),
      result.imitate_ms, result.describe_ms, shown(a.out).c_str());
}

}  // namespace

void add_describe_command(CLI::App& app) {
  auto a = std::make_shared<DescribeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "describe",
      "Describe places: a VO export's keyframes (imitated LiDAR scans), real LiDAR scans, or "
      "keyframe images (gist, bow)");
  cmd->add_option("--method", a->config.method, "sc | m2dp | delight | bev | gist | bow")->required();
  add_mode_option(*cmd, a->config);
  add_config_option(*cmd, a->config);
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--threads", a->threads, "threads describing scans (imitation is sequential)")
      ->check(finite_in(1, kMaxThreads))
      ->capture_default_str();
  CLI::Option_group* vo = cmd->add_option_group("a VO export", "sc, m2dp, delight");
  vo->add_option("--poses", a->poses, "SO-DSO poses_history_file.txt");
  vo->add_option("--points", a->points, "SO-DSO pts_history_file.txt (or .gz)");
  vo->add_option("--reset-ids", a->reset_ids,
                 "default mode: file of keyframe ids where the VO reset (else detected)");
  CLI::Option_group* lidar = cmd->add_option_group("real LiDAR scans", "sc, m2dp, delight");
  lidar->add_option("--lidar", a->lidar,
                    "files or folders (KITTI .bin / .bin.gz, .pcd, .ply), one place each, z up");
  CLI::Option_group* images = cmd->add_option_group("keyframe images", "gist, bow");
  images->add_option("--kitti", a->images.kitti, "KITTI-layout image sequence");
  images->add_option("--keyframes", a->images.keyframes,
                     "a describe output of the same drive (its incoming_id_file.txt: the places)");
  images->add_option("--vocab", a->images.vocab,
                     "bow: vocabulary (ours, ORBvoc.txt, DBoW2/3 .yml)");
  run_writing_dir(cmd, a, run_describe);
}

}  // namespace loopscan::cli
