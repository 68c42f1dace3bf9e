// loopscan run: stereo images -> VO -> imitated scans and descriptors (every method) ->
// evaluation against ground truth -> one HTML report. What `vo`, `describe` and `evaluate` do,
// in one process.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "evaluation_outputs.hpp"
#include "loopscan/core/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "options.hpp"
#include "signature_outputs.hpp"
#include "vo_outputs.hpp"

namespace loopscan::cli {
namespace {

struct RunArgs {
  VoArgs vo;
  std::string out, mode = "default";
  std::vector<std::string> methods = {"sc", "m2dp", "delight"};
  int threads = 2;
};

struct MethodRun {
  Method method;
  SequenceSignatures signatures;
  eval::PlaceEvaluation evaluation;
  bool evaluated = false;
};

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

report::Figure trajectory_figure(const VoResult& vo, const std::vector<Eigen::Vector3d>& gt) {
  // The VO starts at the identity; drawn from the first frame's ground-truth pose.
  report::Series truth{"ground truth", {}, {}, "#444444"}, estimate{"VO", {}, {}, "#d62728"};
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
  if (!gt.empty()) {
    const auto rows = io::read_kitti_poses(vo.gt_path);
    anchor.matrix().topRows<3>() = rows[static_cast<std::size_t>(vo.run.frame_ids.front())];
  }
  for (std::size_t i = 0; i < vo.run.trajectory.size(); ++i) {
    const Eigen::Vector3d p = anchor * vo.run.trajectory[i].translation();
    estimate.x.push_back(p.x());
    estimate.y.push_back(p.z());
    if (!gt.empty()) {
      truth.x.push_back(gt[i].x());
      truth.y.push_back(gt[i].z());
    }
  }
  std::vector<report::Series> series;
  if (!gt.empty()) series.push_back(truth);
  series.push_back(estimate);
  return {"Trajectory seen from above (x, z)", report::map_plot_svg(series, "Trajectory")};
}

void run_all(const RunArgs& a) {
  const Mode mode = parse_mode(a.mode);
  VoArgs vo_args = a.vo;
  vo_args.out = a.out + "/vo";
  std::printf("[1/3] stereo VO on %s\n", a.vo.kitti.c_str());
  const VoResult vo = run_vo_and_write(vo_args);
  std::vector<Eigen::Vector3d> gt_by_frame;  // per trajectory entry
  std::vector<Eigen::Vector3d> gt_rows;
  if (!vo.gt_path.empty()) {
    gt_rows = io::read_positions(vo.gt_path, io::GtFormat::Kitti);
    for (int f : vo.run.frame_ids) gt_by_frame.push_back(gt_rows[static_cast<std::size_t>(f)]);
  } else {
    std::printf("no ground truth (%s/poses.txt or --gt): describing without evaluation\n",
                a.vo.kitti.c_str());
  }

  std::vector<MethodRun> runs;
  for (const std::string& name : a.methods) {
    MethodRun r{parse_method(name), {}, {}, false};
    std::printf("[2/3] describing with %s\n", name.c_str());
    std::fflush(stdout);
    SequenceOptions options = SequenceOptions::make(r.method, mode);
    options.threads = std::max(1, a.threads);
    r.signatures = describe_sequence(vo.run.keyframe_poses, vo.run.points, options);
    const std::string dir = a.out + "/" + method_name(r.method);
    write_signatures(dir, r.signatures, r.method);
    if (!gt_rows.empty() && !r.signatures.signatures.empty()) {
      std::vector<Eigen::Vector3d> positions;
      for (int id : r.signatures.keyframe_ids) positions.push_back(gt_rows[static_cast<std::size_t>(id)]);
      eval::PlaceEvaluationOptions eo;
      eo.method = r.method;
      eo.threads = std::max(1, a.threads);
      eo.precision = mode == Mode::Reference ? Precision::Double : Precision::Float;
      eo.reference_quirks = mode == Mode::Reference;
      r.evaluation = eval::evaluate_places(r.signatures.signatures, r.signatures.signatures,
                                           positions, positions, eo);
      r.evaluated = true;
      const nlohmann::json metrics = {{"method", method_name(r.method)},
                                      {"mode", mode_name(mode)},
                                      {"auc", r.evaluation.pr.auc},
                                      {"recall_at_100_precision", r.evaluation.pr.recall_at_100_precision},
                                      {"f1_max", r.evaluation.pr.f1_max},
                                      {"n_queries", r.evaluation.pr.n_queries},
                                      {"n_gt_loops", r.evaluation.pr.n_gt_loops},
                                      {"query_ms", r.evaluation.query_ms}};
      write_evaluation(dir, r.signatures.keyframe_ids, r.signatures.keyframe_ids, r.evaluation.pr,
                       metrics, method_name(r.method));
    }
    if (r.signatures.signatures.empty()) {
      std::printf("%s: no signatures (too few keyframes for the imitation's warm-up)\n",
                  name.c_str());
    }
    runs.push_back(std::move(r));
  }

  std::printf("[3/3] report\n\n%-8s %8s %8s %8s %9s %10s %10s %10s\n", "method", "AUC", "R@100P",
              "F1max", "GT loops", "imitate", "describe", "query");
  nlohmann::json summary = {{"vo", vo.summary}, {"methods", nlohmann::json::array()}};
  report::HtmlPage page;
  page.title = "loopscan run: " + a.vo.kitti;
  page.paragraphs.push_back(
      "Stereo VO on " + std::to_string(vo.run.frame_ids.size()) + " frames (" +
      std::to_string(vo.run.keyframes.size()) + " keyframes, " +
      std::to_string(vo.run.reset_frames.size()) + " resets) at " + fixed(vo.run.fps, 1) +
      " frames/s; " + fixed(vo.run.mean_points_per_keyframe, 0) + " exported points per keyframe.");
  if (vo.summary.contains("metrics")) {
    const nlohmann::json& m = vo.summary["metrics"];
    report::Table t{"Odometry accuracy (KITTI protocol)",
                    {"segments", "translation %", "rotation deg/100 m", "ATE m", "path m"},
                    {}};
    auto cell = [](const nlohmann::json& x, int d) {
      return x.is_null() ? std::string("n/a") : fixed(x.get<double>(), d);
    };
    t.rows.push_back({std::to_string(m["segments"].get<int>()), cell(m["translation_percent"], 2),
                      cell(m["rotation_deg_per_100m"], 3), cell(m["ate_rmse_m"], 3),
                      cell(m["path_length_m"], 0)});
    page.tables.push_back(t);
  }
  report::Table places{"Place recognition (same session: 10 m, |i - j| >= 100)",
                       {"method", "AUC", "recall@100%P", "F1 max", "GT loops", "imitate ms/kf",
                        "describe ms/kf", "query ms"},
                       {}};
  std::vector<report::Series> curves;
  for (const MethodRun& r : runs) {
    const eval::PrResult& pr = r.evaluation.pr;
    std::printf("%-8s %8.4f %8.4f %8.4f %9d %10.3f %10.3f %10.3f\n",
                method_name(r.method).c_str(), pr.auc, pr.recall_at_100_precision, pr.f1_max,
                pr.n_gt_loops, r.signatures.imitate_ms, r.signatures.describe_ms,
                r.evaluation.query_ms);
    summary["methods"].push_back({{"method", method_name(r.method)},
                                  {"signatures", r.signatures.signatures.size()},
                                  {"evaluated", r.evaluated},
                                  {"auc", pr.auc},
                                  {"recall_at_100_precision", pr.recall_at_100_precision},
                                  {"f1_max", pr.f1_max},
                                  {"n_gt_loops", pr.n_gt_loops},
                                  {"imitate_ms", r.signatures.imitate_ms},
                                  {"describe_ms", r.signatures.describe_ms},
                                  {"query_ms", r.evaluation.query_ms}});
    places.rows.push_back({method_name(r.method), fixed(pr.auc, 4),
                           fixed(pr.recall_at_100_precision, 4), fixed(pr.f1_max, 4),
                           std::to_string(pr.n_gt_loops), fixed(r.signatures.imitate_ms, 3),
                           fixed(r.signatures.describe_ms, 3), fixed(r.evaluation.query_ms, 3)});
    if (r.evaluated) curves.push_back(report::pr_series(pr.curve, method_name(r.method)));
  }
  page.tables.push_back(places);
  page.figures.push_back(trajectory_figure(vo, gt_by_frame));
  if (!curves.empty())
    page.figures.push_back({"Precision-recall", report::pr_curve_svg(curves, "Precision-recall")});
  io::write_file_atomic(a.out + "/summary.json", summary.dump(1) + "\n");
  io::write_file_atomic(a.out + "/report.html", report::render_html(page));
  std::printf("\n-> %s/report.html\n", a.out.c_str());
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto a = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand(
      "run", "Stereo images -> VO -> describe -> evaluate -> report, in one go");
  add_vo_options(*cmd, a->vo);
  cmd->get_option("--out")->description("output directory (vo/, <method>/, report.html)");
  cmd->add_option("--methods", a->methods, "descriptors to run")->capture_default_str();
  cmd->add_option("--mode", a->mode, "reference | default")->capture_default_str();
  cmd->add_option("--threads", a->threads, "threads describing and matching")
      ->capture_default_str();
  cmd->callback([a] {
    a->out = a->vo.out;
    run_all(*a);
  });
}

}  // namespace loopscan::cli
