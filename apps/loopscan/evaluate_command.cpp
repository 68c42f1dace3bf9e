// loopscan evaluate: signatures + ground truth -> metrics.json, pr.csv, matches.csv, pr.svg
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "evaluation_outputs.hpp"
#include "image_commands.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/signature_set.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "progress.hpp"

namespace loopscan::cli {
namespace {

struct EvaluateArgs {
  std::string method, signatures, ids, gt, gt_format = "kitti", against, gt2, fusion,
                                           mode = "default", out;
  double threshold_m = -1;
  double structure_weight = 2.0;  // the paper's w_s
  int mask = -1;
};

void run_evaluate(const EvaluateArgs& a) {
  if (is_image_method(a.method)) {
    run_image_evaluate({a.method, a.signatures, a.gt, a.gt_format, a.against, a.gt2, a.out,
                        a.threshold_m, a.mask});
    return;
  }
  const Method method = parse_method_or_image(a.method);
  const Mode mode = parse_mode(a.mode);
  const Fusion fusion = a.fusion.empty() ? default_fusion(mode) : parse_fusion(a.fusion);
  io::SignatureSet queries = io::load_signature_set(a.signatures, method, a.ids);
  io::attach_positions(queries, a.gt, a.gt_format);
  const bool cross = !a.against.empty();
  io::SignatureSet db = queries;
  if (cross) {
    if (a.gt2.empty()) throw std::invalid_argument("--against needs --gt2");
    db = io::load_signature_set(a.against, method);
    io::attach_positions(db, a.gt2, a.gt_format);
  }
  if (queries.places.empty() || db.places.empty()) {
    throw std::invalid_argument("nothing to evaluate: no signatures in " +
                                (queries.places.empty() ? a.signatures : a.against));
  }

  eval::PlaceEvaluationOptions options = eval::PlaceEvaluationOptions::make(method, mode);
  options.fusion = fusion;
  options.structure_weight = a.structure_weight;
  options.protocol = cross ? eval::cross_session_protocol() : eval::same_session_protocol();
  if (a.threshold_m > 0) options.protocol.threshold_m = a.threshold_m;
  if (a.mask >= 0) options.protocol.mask_width = a.mask;
  StepProgress progress("evaluate " + method_name(method), "difference-matrix rows");
  options.progress = progress.callback();
  const eval::PlaceEvaluation ev =
      eval::evaluate_places(queries.places, db.places, queries.positions, db.positions, options);
  progress.finish(options.two_passes() ? " (adaptive fusion: two passes over the queries)" : "");

  nlohmann::json metrics = {
      {"method", method_name(method)},
      {"fusion", method == Method::Delight ? "intensity-only" : fusion_name(fusion)},
      {"mode", mode_name(mode)},
      {"protocol",
       {{"threshold_m", options.protocol.threshold_m},
        {"mask_width", options.protocol.mask_width},
        {"cross_session", cross}}},
      {"n_database", db.places.size()},
      {"query_ms", ev.query_ms}};
  metrics.update(pr_metrics(ev.pr));
  const eval::DirectionSplit split = eval::split_by_direction(
      ev.pr, queries.positions, db.positions, queries.headings, db.headings, options.protocol);
  metrics["by_direction"] = direction_metrics(split);
  if (fusion == Fusion::Adaptive && method != Method::Delight) {
    const FusionWeights& w = ev.weights;
    metrics["fusion_weights"] = {
        {"structure", w.structure},          {"intensity", w.intensity},
        {"agreement", w.agreement},          {"chance", w.chance},
        {"reliability", w.reliability},      {"structure_peak", w.structure_peak},
        {"intensity_peak", w.intensity_peak}};
  }
  const std::string title = method_name(method) + " (" + metrics["fusion"].get<std::string>() + ")";
  write_evaluation(a.out, queries.keyframe_ids, db.keyframe_ids, ev.pr, metrics, title);
  std::printf(
      "%s: AUC %.4f, recall@100%%P %.4f, F1-max %.4f, %d GT loops / %d queries, "
      "%.3f ms per query -> %s\n",
      title.c_str(), ev.pr.auc, ev.pr.recall_at_100_precision, ev.pr.f1_max, ev.pr.n_gt_loops,
      ev.pr.n_queries, ev.query_ms, shown(a.out).c_str());
  print_direction_split(split);
}

}  // namespace

void add_evaluate_command(CLI::App& app) {
  auto args = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand("evaluate", "Match places and compute PR, AUC, recall, F1");
  cmd->add_option("--method", args->method, "sc | m2dp | delight | gist | bow")->required();
  cmd->add_option("--signatures", args->signatures, "describe output dir or signature file")
      ->required();
  cmd->add_option("--ids", args->ids, "incoming_id_file.txt (when --signatures is a file)");
  cmd->add_option("--gt", args->gt, "ground truth: KITTI poses or RobotCar GPS")->required();
  cmd->add_option("--gt-format", args->gt_format, "kitti | robotcar")->capture_default_str();
  cmd->add_option("--against", args->against, "database session (cross-session evaluation)");
  cmd->add_option("--gt2", args->gt2, "ground truth of the --against session");
  cmd->add_option("--fusion", args->fusion,
                  "adaptive (default mode's default) | fused (the paper's; reference mode's "
                  "default) | structure | intensity");
  cmd->add_option("--structure-weight", args->structure_weight,
                  "w_s of the fusion w_s z(structure) + z(intensity)")
      ->check(finite_in(0.0, 1000.0))
      ->capture_default_str();
  cmd->add_option("--mode", args->mode, "reference (double, Matlab quirks) | default")
      ->capture_default_str();
  cmd->add_option("--threshold", args->threshold_m, "loop distance in m (10 same / 25 cross)")
      ->check(finite_in(1e-3, 1e6));
  cmd->add_option("--mask", args->mask, "excluded index band |i-j| < mask (100 same / 0 cross)")
      ->check(finite_in(0, kMaxCount));
  cmd->add_option("--out", args->out, "output directory")->required();
  run_writing_dir(cmd, args, run_evaluate);
}

}  // namespace loopscan::cli
