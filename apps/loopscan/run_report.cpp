#include "run_report.hpp"

#include <cstdio>

#include "evaluation_outputs.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "options.hpp"

namespace loopscan::cli {
void write_method_evaluation(const MethodRun& r, const std::string& dir, Mode mode) {
  nlohmann::json metrics = {
      {"method", r.name}, {"mode", mode_name(mode)}, {"query_ms", r.query_ms}};
  metrics.update(pr_metrics(r.pr));
  metrics["by_direction"] = direction_metrics(r.by_direction);
  write_evaluation(dir, r.keyframe_ids, r.keyframe_ids, r.pr, metrics, r.name);
}

std::vector<report::Series> add_method_results(const std::vector<MethodRun>& runs,
                                               report::HtmlPage& page, nlohmann::json& summary) {
  report::Table places_table{"Accuracy (same session: 10 m, |i - j| >= 100)",
                             {"method", "AUC", "recall@100%P", "F1 max", "GT loops", "places"},
                             {}};
  report::Table times{
      "Run time per keyframe (ms, one thread)", {"method", "prepare", "describe", "query"}, {}};
  report::Table direction{
      "By direction of the revisit (top-1 correct / GT loops; same: headings < 90 deg apart)",
      {"method", "same: top-1", "same: AUC", "opposite: top-1", "opposite: AUC"},
      {}};
  std::vector<report::Series> curves;
  for (const MethodRun& r : runs) {
    const eval::PrResult& pr = r.pr;
    std::printf("%-8s %8.4f %8.4f %8.4f %9d %7zu %11.3f %11.3f %10.3f\n", r.name.c_str(), pr.auc,
                pr.recall_at_100_precision, pr.f1_max, pr.n_gt_loops, r.keyframe_ids.size(),
                r.prepare_ms, r.describe_ms, r.query_ms);
    nlohmann::json entry = {
        {"method", r.name},           {"places", r.keyframe_ids.size()}, {"evaluated", r.evaluated},
        {"prepare_ms", r.prepare_ms}, {"describe_ms", r.describe_ms},    {"query_ms", r.query_ms}};
    entry.update(pr_metrics(pr));
    if (r.evaluated) entry["by_direction"] = direction_metrics(r.by_direction);
    summary["methods"].push_back(entry);
    places_table.rows.push_back({r.name, fixed(pr.auc, 4), fixed(pr.recall_at_100_precision, 4),
                                 fixed(pr.f1_max, 4), std::to_string(pr.n_gt_loops),
                                 std::to_string(r.keyframe_ids.size())});
    times.rows.push_back(
        {r.name, fixed(r.prepare_ms, 3), fixed(r.describe_ms, 3), fixed(r.query_ms, 3)});
    if (r.evaluated) {
      curves.push_back(report::pr_series(pr.curve, r.name));
      std::vector<std::string> row = {r.name};
      for (std::string& c : direction_cells(r.by_direction)) row.push_back(std::move(c));
      direction.rows.push_back(std::move(row));
    }
  }
  page.tables.push_back(places_table);
  page.tables.push_back(direction);
  page.tables.push_back(times);
  return curves;
}

}  // namespace loopscan::cli
