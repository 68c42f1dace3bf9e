// loopscan run: stereo images -> VO -> imitated scans and descriptors (every method, plus the
// GIST / BoW image baselines on the same keyframes) -> evaluation against ground truth -> one
// HTML report. What `vo`, `describe` and `evaluate` do,
// in one process.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "loopscan/baselines/baseline_matching.hpp"
#include "loopscan/baselines/describe_images.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/sodso.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "outputs/closure.hpp"
#include "outputs/closure_figures.hpp"
#include "outputs/evaluation.hpp"
#include "outputs/images.hpp"
#include "outputs/reproduce_script.hpp"
#include "outputs/run_report.hpp"
#include "outputs/signatures.hpp"
#include "outputs/vo.hpp"

namespace loopscan::cli {
namespace {

struct RunArgs {
  VoArgs vo;
  ConfigFlags config;
  std::string out, vocab;
  std::vector<std::string> methods = {"sc", "m2dp", "delight", "gist"};
  int threads = 2;
};

// The configuration `run` used for one method: what its folder's config.yaml says.
Configuration for_method(const Configuration& c, const std::string& name) {
  Configuration m = c;
  parse_method_name(name, m.method, m.image_baseline);
  return m;
}

void run_all(const RunArgs& a) {
  // Every listed method is described and evaluated; loops close with Scan Context (a method
  // the file names is not used).
  Configuration c = resolve_configuration(a.config);
  c.method = Method::ScanContext;
  c.image_baseline.reset();
  require_loop_closing(c, a.config);
  const Mode mode = c.mode;
  for (const std::string& name : a.methods) {  // before the VO runs
    for_method(c, name);                       // a typo is named
    if (name == "bow" && a.vocab.empty())
      throw std::invalid_argument("--methods bow needs --vocab");
  }
  VoArgs vo_args = a.vo;
  vo_args.out = a.out + "/vo";
  // One numbered line per step; the parts of each end with their own time (progress.hpp).
  StepCounter steps(3 + static_cast<int>(a.methods.size()));
  steps.next("stereo VO on " + a.vo.kitti);
  VoResult vo = run_vo_and_write(vo_args, c);
  // Describe what the VO wrote (the SO-DSO files round points to 0.1 mm), as `describe` would.
  vo.run.keyframe_poses = io::read_sodso_poses(vo_args.out + "/poses_history_file.txt");
  vo.run.points = io::read_sodso_points(vo_args.out + "/pts_history_file.txt");
  std::vector<Eigen::Vector3d> gt_by_frame;          // per trajectory entry
  std::vector<Eigen::Vector3d> gt_rows, gt_forward;  // per frame id: position, heading
  if (!vo.gt_path.empty()) {
    for (const auto& T : vo.gt_poses) gt_rows.push_back(T.col(3));
    for (const auto& T : vo.gt_poses) gt_forward.push_back(T.col(2).normalized());  // as read
    for (int f : vo.run.frame_ids) gt_by_frame.push_back(gt_rows[static_cast<std::size_t>(f)]);
  } else {
    std::printf("no ground truth (%s/poses.txt or --gt): describing without evaluation\n",
                a.vo.kitti.c_str());
  }

  // LiDAR-style methods first: their places (keyframes after the imitation's warm-up) are the
  // places the image baselines describe, so that all methods share one protocol.
  std::vector<std::string> order;
  for (const std::string& name : a.methods)
    if (!is_image_method(name)) order.push_back(name);
  for (const std::string& name : a.methods)
    if (is_image_method(name)) order.push_back(name);
  std::vector<int> places;
  for (const KeyframePose& k : vo.run.keyframe_poses) places.push_back(k.id);
  bool places_from_lidar = false;
  std::vector<MethodRun> runs;
  for (const std::string& name : order) {
    steps.next(name + ": describe the keyframes" + (gt_rows.empty() ? "" : ", then match them"));
    MethodRun r;
    r.name = name;
    r.protocol = c.evaluation.same_session;
    const std::string dir = a.out + "/" + name;
    auto positions_of = [&](const std::vector<int>& ids) {
      std::vector<Eigen::Vector3d> positions;
      for (int id : ids) positions.push_back(gt_rows[static_cast<std::size_t>(id)]);
      return positions;
    };
    auto split = [&](const std::vector<int>& ids) {  // same- vs opposite-direction revisits
      std::vector<Eigen::Vector3d> headings;
      for (int id : ids) headings.push_back(gt_forward[static_cast<std::size_t>(id)]);
      const std::vector<Eigen::Vector3d> positions = positions_of(ids);
      return eval::split_by_direction(r.pr, positions, positions, headings, headings, r.protocol);
    };
    if (!is_image_method(name)) {
      const Configuration cm = for_method(c, name);
      SequenceOptions options = sequence_options(cm);
      options.threads = std::max(1, a.threads);
      const SequenceSignatures sig = with_progress(
          "  describe", "keyframes", a.vo.quiet, options.progress,
          [&] { return describe_as_written(vo.run.keyframe_poses, vo.run.points, options, cm); });
      write_signatures(dir, sig, cm);
      r.keyframe_ids = sig.keyframe_ids;
      r.prepare_ms = sig.imitate_ms;
      r.describe_ms = sig.describe_ms;
      if (!places_from_lidar && !sig.keyframe_ids.empty()) {
        places = sig.keyframe_ids;
        places_from_lidar = true;
      }
      if (sig.signatures.empty()) {
        std::printf("%s: no signatures (too few keyframes for the imitation's warm-up)\n",
                    name.c_str());
      } else if (!gt_rows.empty()) {
        eval::PlaceEvaluationOptions eo = place_evaluation_options(cm, false);
        eo.threads = std::max(1, a.threads);
        const std::vector<Eigen::Vector3d> positions = positions_of(sig.keyframe_ids);
        const eval::PlaceEvaluation ev =
            with_progress("  match", "rows", a.vo.quiet, eo.progress, [&] {
              return eval::evaluate_places(sig.signatures, sig.signatures, positions, positions,
                                           eo);
            });
        r.pr = ev.pr;
        r.query_ms = ev.query_ms;
        r.by_direction = split(r.keyframe_ids);
        r.evaluated = true;
      }
    } else {
      const io::KittiSequence sequence = io::open_kitti_sequence(a.vo.kitti);
      baselines::ImageDescriptors d;
      StepProgress describing("  describe", "images", a.vo.quiet);
      if (name == "gist") {
        r.has_describe_step = false;
        d = baselines::describe_gist(sequence, places, gist_config(c), std::max(1, a.threads),
                                     describing.callback());
      } else {
        d = baselines::describe_bow(sequence, places, baselines::read_vocabulary(a.vocab),
                                    c.baselines.orb, describing.callback());
      }
      describing.finish();
      r.keyframe_ids = places;
      r.prepare_ms = d.extract_ms;
      r.describe_ms = d.transform_ms;
      write_image_descriptors(dir, d, places, for_method(c, name));
      if (!gt_rows.empty() && !places.empty()) {
        const int mask = r.protocol.mask_width;
        const baselines::BaselineMatches m =
            name == "gist" ? baselines::best_gist_matches(d.gist, d.gist, mask)
                           : baselines::best_bow_matches(d.bow, d.bow, mask);
        const std::vector<Eigen::Vector3d> positions = positions_of(places);
        r.pr = eval::evaluate_matches(m.matches, positions, positions, r.protocol,
                                      mode == Mode::Reference);
        r.query_ms = m.query_ms;
        r.by_direction = split(r.keyframe_ids);
        r.evaluated = true;
      }
    }
    if (r.evaluated) write_method_evaluation(r, dir, mode);
    runs.push_back(std::move(r));
  }

  steps.next("loop closing (Scan Context, verified, pose graph)");
  std::optional<GroundTruth> gt;
  if (!vo.gt_path.empty()) gt = read_ground_truth(vo.gt_path, vo.run.keyframe_poses);
  const ClosureOutputs closure =
      close_vo_run(a.out + "/closure", vo.run.keyframe_poses, vo.run.points, vo.run.reset_frames,
                   gt, c, !a.vo.quiet);
  const nlohmann::json& closing = closure.metrics;
  steps.next("report");
  std::printf("\n%-8s %8s %8s %8s %9s %7s %11s %11s %10s\n", "method", "AUC", "R@100P", "F1max",
              "GT loops", "places", "prepare ms", "describe ms", "query ms");
  nlohmann::json summary = {
      {"vo", vo.summary}, {"methods", nlohmann::json::array()}, {"closure", closing}};
  report::HtmlPage page;
  page.title = "loopscan run: " + a.vo.kitti;
  page.paragraphs.push_back(
      "Stereo VO on " + std::to_string(vo.run.frame_ids.size()) + " frames (" +
      std::to_string(vo.run.keyframes.size()) + " keyframes, " +
      std::to_string(vo.run.reset_frames.size()) + " resets) at " + fixed(vo.run.fps, 1) +
      " frames/s; " + fixed(vo.run.mean_points_per_keyframe, 0) + " exported points per keyframe.");
  page.paragraphs.push_back(
      "Every method is evaluated on the same places (the LiDAR-style methods' keyframes; the "
      "image baselines describe the left image of each) under the same-session protocol. "
      "Prepare = imitating the scan (sc, m2dp, delight) or extracting GIST / ORB (gist, bow); "
      "describe = the descriptor (sc, m2dp, delight) or the BoW transform; all per keyframe "
      "and measured as one thread's work; query = one place against all.");
  if (vo.summary.contains("metrics")) {
    const nlohmann::json& m = vo.summary["metrics"];
    report::Table t{"Odometry accuracy (KITTI protocol)",
                    {"segments", "translation %", "rotation deg/100 m", "ATE m",
                     "ATE after Sim(3) m", "Sim(3) scale", "path m"},
                    {}};
    auto cell = [](const nlohmann::json& x, int d) {
      return x.is_null() ? std::string("n/a") : fixed(x.get<double>(), d);
    };
    t.rows.push_back({std::to_string(m["segments"].get<int>()), cell(m["translation_percent"], 2),
                      cell(m["rotation_deg_per_100m"], 3), cell(m["ate_rmse_m"], 3),
                      cell(m["ate_sim3_rmse_m"], 3), cell(m["sim3_scale"], 4),
                      cell(m["path_length_m"], 0)});
    page.tables.push_back(t);
  }
  std::vector<report::Series> curves =
      add_method_results(runs, std::max(1, a.threads), page, summary);
  page.tables.push_back(closing_table(closing));
  for (report::Figure& f : trajectory_figures(vo, gt_by_frame)) page.figures.push_back(f);
  for (const MethodRun& r : runs) {  // the first method with revisits, Scan Context by default
    if (!r.evaluated || r.pr.n_gt_loops == 0) continue;
    page.figures.push_back(recognition_figure(r, gt_rows));
    break;
  }
  page.figures.push_back(
      {"Loop closing: keyframes before and after, accepted loops", closure.figures.map});
  if (!closure.figures.error.empty())
    page.figures.push_back({"Loop closing: position error along the drive", closure.figures.error});
  if (!curves.empty())
    page.figures.push_back({"Precision-recall", report::pr_curve_svg(curves, "Precision-recall")});
  io::write_file_atomic(a.out + "/summary.json", summary.dump(1) + "\n");
  io::write_file_atomic(a.out + "/report.html", report::render_html(page));
  write_used_configuration(a.out, c, false);
  write_reproduce_script(a.out + "/reproduce.sh",
                         run_script(runs, a.vo.kitti, a.vocab, vo.gt_path));
  std::printf("\nloop closing: %d loops accepted", closing["loops"]["accepted"].get<int>());
  if (closing.contains("ate_after_m")) {
    std::printf(", keyframe ATE %.3f m -> %.3f m", closing["ate_before_m"].get<double>(),
                closing["ate_after_m"].get<double>());
  }
  std::printf(
      "\nrecompute the table from the written files: sh %s/reproduce.sh\n-> %s/report.html\n",
      shown(a.out).c_str(), shown(a.out).c_str());
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* cmd =
      app.add_subcommand("run", "Stereo images -> VO -> describe -> evaluate -> report, in one go");
  add_vo_options(*cmd, a->vo);
  cmd->get_option("--out")->description("output directory (vo/, <method>/, report.html)");
  cmd->add_option("--methods", a->methods, "sc m2dp delight gist bow (bow needs --vocab)")
      ->capture_default_str();
  cmd->add_option("--vocab", a->vocab, "bow: vocabulary (ours or ORBvoc.txt)");
  add_mode_option(*cmd, a->config);
  add_config_option(*cmd, a->config);
  cmd->add_option("--threads", a->threads, "threads describing and matching")
      ->check(finite_in(1, kMaxThreads))
      ->capture_default_str();
  cmd->callback([cmd, a] {
    RunArgs args = *a;
    args.out = args.vo.out;
    refuse_inputs_inside(*cmd, args.out);
    with_output_dir(args.out, [&] { run_all(args); });
  });
}

}  // namespace loopscan::cli
