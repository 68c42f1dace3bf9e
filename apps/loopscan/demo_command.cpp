// loopscan demo: the whole method on a built-in synthetic street scene, no download needed.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "loopscan/core/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "loopscan/sim/tiny_scene.hpp"

namespace loopscan::cli {
namespace {

struct DemoArgs {
  std::string out = "demo";
  unsigned seed = 7;
};

void run_demo(const DemoArgs& a) {
  sim::TinySceneConfig config;
  config.seed = a.seed;
  const sim::TinyScene scene = sim::make_tiny_scene(config);
  std::printf("tiny scene: %zu keyframes, %zu points, two laps around a %.0f m block\n",
              scene.poses.size(), scene.points.size(), config.block_m);
  std::printf("%-8s %8s %12s %8s %11s %11s %9s\n", "method", "AUC", "recall@100P", "F1-max",
              "imitate ms", "describe ms", "query ms");
  std::vector<report::Series> curves;
  nlohmann::json table = nlohmann::json::array();
  for (Method method : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    const SequenceOptions options = SequenceOptions::make(method, Mode::Default);
    const SequenceSignatures sigs = describe_sequence(scene.poses, scene.points, options);
    std::vector<Eigen::Vector3d> positions;
    for (int id : sigs.keyframe_ids) positions.push_back(scene.positions[id]);
    eval::PlaceEvaluationOptions eo;
    eo.method = method;
    const eval::PlaceEvaluation ev =
        eval::evaluate_places(sigs.signatures, sigs.signatures, positions, positions, eo);
    std::printf("%-8s %8.4f %12.4f %8.4f %11.3f %11.3f %9.3f\n", method_name(method).c_str(),
                ev.pr.auc, ev.pr.recall_at_100_precision, ev.pr.f1_max, sigs.imitate_ms,
                sigs.describe_ms, ev.query_ms);
    curves.push_back(report::pr_series(ev.pr.curve, method_name(method)));
    table.push_back({{"method", method_name(method)},
                     {"auc", ev.pr.auc},
                     {"recall_at_100_precision", ev.pr.recall_at_100_precision},
                     {"f1_max", ev.pr.f1_max},
                     {"n_gt_loops", ev.pr.n_gt_loops},
                     {"imitate_ms", sigs.imitate_ms},
                     {"describe_ms", sigs.describe_ms},
                     {"query_ms", ev.query_ms}});
  }
  std::filesystem::create_directories(a.out);
  io::write_file_atomic(a.out + "/metrics.json", table.dump(1) + "\n");
  io::write_file_atomic(a.out + "/pr.svg",
                        report::pr_curve_svg(curves, "Tiny scene, same session (default mode)"));
  std::printf("wrote %s/metrics.json and %s/pr.svg\n", a.out.c_str(), a.out.c_str());
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand("demo", "Run all three descriptors on a built-in scene");
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--seed", args->seed, "scene seed")->capture_default_str();
  cmd->callback([args] { run_demo(*args); });
}

}  // namespace loopscan::cli
