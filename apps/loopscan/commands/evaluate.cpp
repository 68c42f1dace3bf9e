// loopscan evaluate: signatures + ground truth -> metrics.json, pr.csv, matches.csv, pr.svg
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/signature_set.hpp"
#include "outputs/evaluation.hpp"
#include "outputs/images.hpp"

namespace loopscan::cli {
namespace {

struct EvaluateArgs {
  ConfigFlags config;
  std::string signatures, ids, gt, against, gt2, fusion, out;
};

void run_evaluate(const EvaluateArgs& a) {
  // The method and mode the signatures were described with, unless the flags or the file say so
  // (a contradiction is refused): reference signatures get the paper's evaluation.
  std::vector<Described> described = {read_described(a.signatures)};
  if (!a.against.empty()) described.push_back(read_described(a.against));
  Configuration c = resolve_configuration(a.config, described, "");
  if (!a.fusion.empty()) c.evaluation.fusion = parse_fusion(a.fusion);
  if (c.image_baseline) {
    run_image_evaluate({a.signatures, a.gt, a.against, a.gt2, a.out}, c);
    return;
  }
  const Method method = c.method;
  const Mode mode = c.mode;
  const Fusion fusion = c.evaluation.fusion;
  io::SignatureSet queries =
      io::load_signature_set(a.signatures, method, a.ids, signature_columns(c));
  io::attach_positions(queries, a.gt);
  const bool cross = !a.against.empty();
  io::SignatureSet db = queries;
  if (cross) {
    if (a.gt2.empty()) throw std::invalid_argument("--against needs --gt2");
    db = io::load_signature_set(a.against, method, "", signature_columns(c));
    io::attach_positions(db, a.gt2);
  }
  if (queries.places.empty() || db.places.empty()) {
    throw std::invalid_argument("nothing to evaluate: no signatures in " +
                                (queries.places.empty() ? a.signatures : a.against));
  }

  eval::PlaceEvaluationOptions options = place_evaluation_options(c, cross);
  StepProgress progress("evaluate " + method_name(method), "difference-matrix rows");
  options.progress = progress.callback();
  const eval::PlaceEvaluation ev =
      eval::evaluate_places(queries.places, db.places, queries.positions, db.positions, options);
  progress.finish(options.two_passes() ? " (adaptive fusion: two passes over the queries)" : "");

  nlohmann::json metrics = {
      {"method", method_name(method)},
      {"fusion", distance_components(method) == 2 ? fusion_name(fusion)
                 : method == Method::Delight ? "intensity-only" : "structure-only"},
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
  if (fusion == Fusion::Adaptive && distance_components(method) == 2) {
    const FusionWeights& w = ev.weights;
    metrics["fusion_weights"] = {{"structure", w.structure},
                                 {"intensity", w.intensity},
                                 {"agreement", w.agreement},
                                 {"chance", w.chance},
                                 {"reliability", w.reliability},
                                 {"structure_peak", w.structure_peak},
                                 {"intensity_peak", w.intensity_peak},
                                 {"structure_sequence", w.structure_sequence},
                                 {"intensity_sequence", w.intensity_sequence}};
  }
  const std::string title = method_name(method) + " (" + metrics["fusion"].get<std::string>() + ")";
  write_evaluation(a.out, queries.keyframe_ids, db.keyframe_ids, ev.pr, metrics, title);
  write_used_configuration(a.out, c);
  std::printf(
      "%s: AUC %.4f, recall@100%%P %.4f, F1-max %.4f, %d GT loops / %d queries, "
      "%.3f ms per query -> %s\n",
      title.c_str(), ev.pr.auc, ev.pr.recall_at_100_precision, ev.pr.f1_max, ev.pr.n_gt_loops,
      ev.pr.n_queries, ev.query_ms, shown(a.out).c_str());
  print_direction_split(split);
}

}  // namespace

void add_evaluate_command(CLI::App& app) {
  auto a = std::make_shared<EvaluateArgs>();
  CLI::App* cmd = app.add_subcommand("evaluate", "Match places and compute PR, AUC, recall, F1");
  cmd->add_option("--signatures", a->signatures, "describe output dir (or a signature file)")
      ->required();
  cmd->add_option("--gt", a->gt, "ground truth: KITTI poses or RobotCar GPS (detected)")
      ->required();
  cmd->add_option("--against", a->against, "database session (cross-session evaluation)");
  cmd->add_option("--gt2", a->gt2, "ground truth of the --against session");
  cmd->add_option("--out", a->out, "output directory")->required();
  cmd->add_option("--method", a->config.method,
                  "sc | m2dp | delight | bev | gist | bow (default: the signatures' own)");
  add_mode_option(*cmd, a->config);
  add_config_option(*cmd, a->config);
  cmd->add_option("--fusion", a->fusion,
                  "adaptive | fused (the paper's) | structure | intensity (default: "
                  "evaluation.fusion, the mode's)")
      ->check(CLI::IsMember({"adaptive", "fused", "structure", "intensity"}));
  cmd->add_option("--ids", a->ids, "incoming_id_file.txt (when --signatures is a file)");
  run_writing_dir(cmd, a, run_evaluate);
}

}  // namespace loopscan::cli
