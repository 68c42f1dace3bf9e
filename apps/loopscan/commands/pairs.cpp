// loopscan pairs: `score label` pairs (higher score = more similar) -> F1-max, AP, PR curve
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/eval/pairwise.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/score_labels.hpp"
#include "loopscan/report/pr_plot.hpp"

namespace loopscan::cli {
namespace {

struct PairsArgs {
  std::string scores, out;
};

void run_pairs(const PairsArgs& a) {
  const eval::PairwiseResult r = eval::evaluate_pairwise(io::read_score_labels(a.scores));
  std::filesystem::create_directories(a.out);
  const nlohmann::json metrics = {{"f1_max", r.f1_max},
                                  {"best_threshold", r.best_threshold},
                                  {"average_precision", r.average_precision},
                                  {"auc_trapezoid", r.auc_trapezoid},
                                  {"n_positive", r.n_positive},
                                  {"n_total", r.n_total}};
  io::write_file_atomic(a.out + "/metrics.json", metrics.dump(1) + "\n");
  std::ostringstream csv;
  csv.precision(10);
  csv << "threshold,precision,recall\n";
  for (std::size_t k = 0; k < r.curve.size(); ++k) {
    csv << (k < r.thresholds.size() ? r.thresholds[k] : 0.0) << ',' << r.curve[k].precision << ','
        << r.curve[k].recall << '\n';
  }
  io::write_file_atomic(a.out + "/pr.csv", csv.str());
  io::write_file_atomic(a.out + "/pr.svg",
                        report::pr_curve_svg({report::pr_series(r.curve, "pairs")}, "pairs"));
  std::printf("F1-max %.10f (threshold %.6g), AP %.6f, %zu positives / %zu pairs -> %s\n", r.f1_max,
              r.best_threshold, r.average_precision, r.n_positive, r.n_total, shown(a.out).c_str());
}

}  // namespace

void add_pairs_command(CLI::App& app) {
  auto args = std::make_shared<PairsArgs>();
  CLI::App* cmd = app.add_subcommand("pairs", "Evaluate pairwise `score label` lists (PR, F1-max)");
  cmd->add_option("--scores", args->scores,
                  "text file (or .gz): `score label` per line, label 0 or 1")
      ->required();
  cmd->add_option("--out", args->out, "output directory")->required();
  run_writing_dir(cmd, args, run_pairs);
}

}  // namespace loopscan::cli
