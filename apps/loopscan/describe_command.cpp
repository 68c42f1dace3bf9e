// loopscan describe: SO-DSO poses + points -> signatures.txt, incoming_id_file.txt, frames.txt,
// timing.json
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "image_commands.hpp"
#include "lidar_describe.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/sodso.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "progress.hpp"
#include "signature_outputs.hpp"

namespace loopscan::cli {
namespace {

struct DescribeArgs {
  std::string method, poses, points, out, mode = "default", reset_ids;
  ImageDescribeArgs images;  // --method gist | bow
  double range_m = 45.0;
  bool range_given = false;
  int threads = 1;
  double lookahead_m = 0;  // forward-only, the paper's scan
  std::string frame;       // empty: the mode's default (sc: camera in default mode; pca)
  double lateral_offset_m = 0;
  std::vector<double> lateral_versions_m;
  std::vector<std::string> lidar;  // real LiDAR scans instead of VO poses + points
  std::string lidar_params = "paper";
};

void run_describe(const DescribeArgs& a) {
  if (is_image_method(a.method)) {
    ImageDescribeArgs images = a.images;
    images.method = a.method;
    images.out = a.out;
    images.threads = std::max(1, a.threads);
    images.reference = parse_mode(a.mode) == Mode::Reference;
    run_image_describe(images);
    return;
  }
  if (!a.lidar.empty()) {
    if (!a.poses.empty() || !a.points.empty() || a.lookahead_m > 0 || !a.frame.empty() ||
        !a.lateral_versions_m.empty() || a.lateral_offset_m != 0)
      throw std::invalid_argument(
          "--lidar describes scans in the mode's default frame: no --poses, --points, "
          "--lookahead, --frame, --lateral-offset or --lateral-versions");
    run_lidar_describe({a.method, a.mode, a.out, a.lidar_params, a.lidar,
                        a.range_given ? a.range_m : 0.0, std::max(1, a.threads)});
    return;
  }
  if (a.poses.empty() || a.points.empty())
    throw std::invalid_argument("--method " + a.method +
                                " needs --poses and --points (or --lidar SCANS)");
  const Method method = parse_method_or_image(a.method);
  const Mode mode = parse_mode(a.mode);
  if (!(a.range_m > 0)) throw std::invalid_argument("--range must be positive");
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

  SequenceOptions options = SequenceOptions::make(method, mode, a.range_m);
  options.threads = std::max(1, a.threads);
  if (mode == Mode::Reference && a.lookahead_m > 0)
    throw std::invalid_argument("--lookahead: reference mode is the paper's forward-only scan");
  if (mode == Mode::Reference && !a.frame.empty() && a.frame != "pca")
    throw std::invalid_argument("--frame: reference mode is the paper's PCA frame");
  options.imitation.lookahead_m = a.lookahead_m;
  ScanContextConfig& sc = options.descriptors.scan_context;
  if (!a.frame.empty()) {
    sc.frame = options.descriptors.m2dp.frame = options.descriptors.delight.frame =
        parse_descriptor_frame(a.frame);
    // The default lateral versions need a keyframe-centred frame.
    if (sc.frame != DescriptorFrame::Camera && sc.frame != DescriptorFrame::Centroid)
      sc.lateral_versions_m.clear();
  }
  if (!a.lateral_versions_m.empty()) {
    if (method != Method::ScanContext)
      throw std::invalid_argument("--lateral-versions: Scan Context only");
    // "--lateral-versions 0": the centred descriptor only.
    sc.lateral_versions_m = a.lateral_versions_m == std::vector<double>{0.0} ? std::vector<double>{}
                                                                             : a.lateral_versions_m;
  }
  if (a.lateral_offset_m != 0) {
    if (method != Method::ScanContext || sc.frame != DescriptorFrame::Camera)
      throw std::invalid_argument("--lateral-offset: Scan Context in the camera frame only");
    sc.lateral_offset_m = a.lateral_offset_m;
  }
  // Frame, mode and versions must agree; said now, before the first scan is described.
  if (method == Method::ScanContext) validate(sc);
  if (mode == Mode::Default) {
    options.reset_ids =
        a.reset_ids.empty() ? detect_vo_resets(poses) : io::read_incoming_ids(a.reset_ids);
  }
  StepProgress progress("describe " + method_name(method), "keyframes");
  options.progress = progress.callback();
  const SequenceSignatures result = describe_sequence(poses, points, options);
  progress.finish(", " + std::to_string(result.signatures.size()) + " signatures");
  if (result.signatures.empty()) {
    std::fprintf(stderr,
                 "warning: no signatures: %zu keyframes, but the first %d after each VO reset "
                 "only accumulate points\n",
                 poses.size(), options.imitation.init_frames);
  }

  write_signatures(a.out, result, method);
  const nlohmann::json timing = {
      {"method", method_name(method)},
      {"mode", mode_name(mode)},
      {"range_m", a.range_m},
      {"lookahead_m", options.imitation.lookahead_m},
      {"frame",
       descriptor_frame_name(method == Method::ScanContext ? options.descriptors.scan_context.frame
                                                           : options.descriptors.m2dp.frame)},
      {"lateral_versions_m", options.descriptors.scan_context.lateral_versions_m},
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
  io::write_file_atomic(a.out + "/timing.json", timing.dump(1) + "\n");
  std::printf(
      "%s (%s): %zu signatures from %zu keyframes; %.3f ms imitate + %.3f ms describe "
      "per keyframe -> %s\n",
      method_name(method).c_str(), mode_name(mode).c_str(), result.signatures.size(), poses.size(),
      result.imitate_ms, result.describe_ms, shown(a.out).c_str());
}

}  // namespace

void add_describe_command(CLI::App& app) {
  auto args = std::make_shared<DescribeArgs>();
  CLI::App* cmd = app.add_subcommand("describe", "Imitate LiDAR scans and describe every keyframe");
  cmd->add_option("--method", args->method, "sc | m2dp | delight | gist | bow")->required();
  cmd->add_option("--poses", args->poses, "SO-DSO poses_history_file.txt (sc, m2dp, delight)");
  cmd->add_option("--points", args->points, "SO-DSO pts_history_file.txt (or .gz)");
  cmd->add_option("--kitti", args->images.kitti, "gist, bow: KITTI-layout image sequence");
  cmd->add_option("--keyframes", args->images.keyframes,
                  "gist, bow: dir with incoming_id_file.txt (the places to describe)");
  cmd->add_option("--vocab", args->images.vocab, "bow: vocabulary (ours or ORBvoc.txt)");
  cmd->add_option("--features", args->images.features, "bow: ORB features per image")
      ->check(finite_in(1, 100000))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--mode", args->mode, "reference | default")->capture_default_str();
  cmd->add_option("--range", args->range_m, "imitated LiDAR range in m")
      ->check(finite_in(0.1, 1000))
      ->each([args](const std::string&) { args->range_given = true; })
      ->capture_default_str();
  cmd->add_option("--lookahead", args->lookahead_m,
                  "two-sided scans: describe a keyframe D m later (0: forward-only, the paper)")
      ->check(finite_in(0.0, 1000.0));
  cmd->add_option("--frame", args->frame,
                  "descriptor frame: pca | camera | gravity-pca | centroid (default: sc camera "
                  "in default mode, else pca)");
  cmd->add_option("--lateral-offset", args->lateral_offset_m,
                  "sc, --frame camera: centre the descriptor X m right of the keyframe")
      ->check(finite_in(-100.0, 100.0));
  cmd->add_option("--lidar", args->lidar,
                  "real LiDAR scans (files or folders: KITTI .bin / .bin.gz, .pcd, .ply), one "
                  "place each, z up; instead of --poses/--points");
  cmd->add_option("--lidar-params", args->lidar_params,
                  "paper (45 m, height range) | scan-context (Scan Context's own: 80 m, max "
                  "height); --range overrides the range")
      ->capture_default_str();
  cmd->add_option("--lateral-versions", args->lateral_versions_m,
                  "sc, camera/centroid frame: also describe each place X m right; queries "
                  "match a place with their best version (default -3.5 -1.75 1.75 3.5; 0: none)")
      ->check(finite_in(-100.0, 100.0));
  cmd->add_option("--threads", args->threads, "threads describing scans (imitation is sequential)")
      ->check(finite_in(1, kMaxThreads))
      ->capture_default_str();
  cmd->add_option("--reset-ids", args->reset_ids,
                  "default mode: file of keyframe ids where the VO reset (else detected)");
  run_writing_dir(cmd, args, run_describe);
}

}  // namespace loopscan::cli
