#include "outputs/evaluation.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/report/pr_plot.hpp"

namespace loopscan::cli {

nlohmann::json pr_metrics(const eval::PrResult& pr) {
  return {{"auc", pr.auc},
          {"recall_at_100_precision", pr.recall_at_100_precision},
          {"f1_max", pr.f1_max},
          {"n_queries", pr.n_queries},
          {"n_gt_loops", pr.n_gt_loops}};
}

nlohmann::json direction_metrics(const eval::DirectionSplit& split) {
  nlohmann::json out;
  for (const auto& [name, d] : {std::pair{"same", &split.same}, {"opposite", &split.opposite}}) {
    nlohmann::json m = pr_metrics(d->pr);
    m["n_loops"] = d->n_loops;
    m["top1_correct"] = d->top1_correct;
    out[name] = m;
  }
  return out;
}

void print_direction_split(const eval::DirectionSplit& split) {
  for (const auto& [name, d] : {std::pair{"same", &split.same}, {"opposite", &split.opposite}}) {
    std::printf("  %-8s direction: AUC %.4f, recall@100%%P %.4f, top-1 correct %d of %d loops\n",
                name, d->pr.auc, d->pr.recall_at_100_precision, d->top1_correct, d->n_loops);
  }
}

std::string fixed(double x, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

std::string protocol_text(const eval::Protocol& p) {
  std::string text =
      fixed(p.threshold_m, p.threshold_m == std::floor(p.threshold_m) ? 0 : 2) + " m, ";
  return text + (p.mask_width > 0 ? "|i - j| >= " + std::to_string(p.mask_width) : "no mask");
}

std::vector<std::string> direction_cells(const eval::DirectionSplit& split) {
  std::vector<std::string> cells;
  for (const eval::DirectionMetrics* d : {&split.same, &split.opposite}) {
    cells.push_back(std::to_string(d->top1_correct) + " / " + std::to_string(d->n_loops));
    cells.push_back(fixed(d->pr.auc, 4));
  }
  return cells;
}

void write_evaluation(const std::string& dir, const std::vector<int>& query_ids,
                      const std::vector<int>& db_ids, const eval::PrResult& pr,
                      const nlohmann::json& metrics, const std::string& title) {
  std::filesystem::create_directories(dir);
  io::write_file_atomic(dir + "/metrics.json", metrics.dump(1) + "\n");
  std::ostringstream curve, matches;
  curve.precision(10);
  matches.precision(10);
  curve << "rank,precision,recall\n";
  for (std::size_t k = 0; k < pr.curve.size(); ++k) {
    curve << k + 1 << ',' << pr.curve[k].precision << ',' << pr.curve[k].recall << '\n';
  }
  matches << "query_id,matched_id,distance,is_true\n";
  for (const eval::RankedMatch& r : pr.ranked) {
    const bool known = r.m.match >= 0 && static_cast<std::size_t>(r.m.match) < db_ids.size();
    matches << query_ids[r.m.query] << ',' << (known ? db_ids[r.m.match] : -1) << ','
            << r.m.distance << ',' << (r.is_true ? 1 : 0) << '\n';
  }
  io::write_file_atomic(dir + "/pr.csv", curve.str());
  io::write_file_atomic(dir + "/matches.csv", matches.str());
  const report::Series series = report::pr_series(pr.curve, title);
  io::write_file_atomic(dir + "/pr.svg", report::pr_curve_svg({series}, title));
}

}  // namespace loopscan::cli
