#include "outputs/run_report.hpp"

#include <algorithm>
#include <cstdio>

#include "cli/options.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "loopscan/report/recognition_map.hpp"
#include "loopscan/report/trajectory_error.hpp"
#include "outputs/evaluation.hpp"

namespace loopscan::cli {
void write_method_evaluation(const MethodRun& r, const std::string& dir, Mode mode) {
  nlohmann::json metrics = {
      {"method", r.name}, {"mode", mode_name(mode)}, {"query_ms", r.query_ms}};
  metrics.update(pr_metrics(r.pr));
  metrics["by_direction"] = direction_metrics(r.by_direction);
  write_evaluation(dir, r.keyframe_ids, r.keyframe_ids, r.pr, metrics, r.name);
}

// evo-style: the VO coloured by its position error against the ground truth, and that error
// over the distance travelled. The VO starts at the identity; it is drawn from the first
// frame's ground-truth pose (KITTI's convention, no alignment).
std::vector<report::Figure> trajectory_figures(const VoResult& vo,
                                               const std::vector<Eigen::Vector3d>& gt) {
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
  if (!gt.empty()) {
    anchor.matrix().topRows<3>() = vo.gt_poses[static_cast<std::size_t>(vo.run.frame_ids.front())];
  }
  std::vector<Eigen::Vector3d> estimate;
  for (const Eigen::Isometry3d& T : vo.run.trajectory) estimate.push_back(anchor * T.translation());
  if (gt.empty()) {
    const std::pair<int, int> axes = report::top_view_axes(estimate);
    return {{"Trajectory seen from above",
             report::map_plot_svg({report::top_view_series("VO", estimate, axes, "#d62728")},
                                  "VO trajectory (no ground truth)", report::axis_label(axes.first),
                                  report::axis_label(axes.second))}};
  }
  report::TrajectoryFigure t;
  t.title = "VO trajectory, anchored at the first frame";
  t.gt = gt;
  t.estimate = estimate;
  t.estimate_name = "VO";
  return {{"Trajectory seen from above, coloured by position error",
           report::trajectory_error_map_svg(t)},
          {"Position error over the distance travelled",
           report::error_over_distance_svg("VO position error (anchored at the first frame)", gt,
                                           {{"VO", estimate}})}};
}

report::Figure recognition_figure(const MethodRun& r,
                                  const std::vector<Eigen::Vector3d>& positions) {
  report::RecognitionMap map;
  map.title = r.name + ", same session";
  for (int id : r.keyframe_ids) map.query_pos.push_back(positions[static_cast<std::size_t>(id)]);
  map.db_pos = map.query_pos;
  map.protocol = r.protocol;
  return {"Places recognised by " + r.name + " at 100% precision",
          report::recognition_map_svg(map, r.pr)};
}

std::vector<report::Series> add_method_results(const std::vector<MethodRun>& runs, int threads,
                                               report::HtmlPage& page, nlohmann::json& summary) {
  const std::string protocol = runs.empty() ? "" : protocol_text(runs.front().protocol);
  report::Table places_table{"Accuracy (same session: " + protocol + ")",
                             {"method", "AUC", "recall@100%P", "F1 max", "GT loops", "places"},
                             {}};
  report::Table times{"Run time per keyframe: ms of one thread's work per item (the run used " +
                          std::to_string(threads) + (threads == 1 ? " thread)" : " threads)"),
                      {"method", "prepare", "describe", "query"},
                      {}};
  report::Table direction{
      "By direction of the revisit (top-1 correct / GT loops; same: headings < 90 deg apart)",
      {"method", "same: top-1", "same: AUC", "opposite: top-1", "opposite: AUC"},
      {}};
  std::vector<report::Series> curves;
  bool any_revisits = false;
  for (const MethodRun& r : runs) {
    const eval::PrResult& pr = r.pr;
    // Without a ground-truth revisit AUC, recall and F1 are undefined, not 0.
    const bool defined = r.evaluated && pr.n_gt_loops > 0;
    any_revisits = any_revisits || defined;
    auto cell = [&](double v) { return defined ? fixed(v, 4) : std::string("n/a"); };
    const std::string describe = r.has_describe_step ? fixed(r.describe_ms, 3) : "-";
    std::printf("%-8s %8s %8s %8s %9d %7zu %11.3f %11s %10.3f\n", r.name.c_str(),
                cell(pr.auc).c_str(), cell(pr.recall_at_100_precision).c_str(),
                cell(pr.f1_max).c_str(), pr.n_gt_loops, r.keyframe_ids.size(), r.prepare_ms,
                describe.c_str(), r.query_ms);
    nlohmann::json entry = {
        {"method", r.name},
        {"places", r.keyframe_ids.size()},
        {"evaluated", r.evaluated},
        {"prepare_ms", r.prepare_ms},
        {"describe_ms", r.has_describe_step ? nlohmann::json(r.describe_ms) : nlohmann::json()},
        {"query_ms", r.query_ms}};
    entry.update(pr_metrics(pr));
    if (!defined) {
      for (const char* key : {"auc", "recall_at_100_precision", "f1_max"}) entry[key] = nullptr;
    }
    if (r.evaluated) entry["by_direction"] = direction_metrics(r.by_direction);
    summary["methods"].push_back(entry);
    places_table.rows.push_back({r.name, cell(pr.auc), cell(pr.recall_at_100_precision),
                                 cell(pr.f1_max), std::to_string(pr.n_gt_loops),
                                 std::to_string(r.keyframe_ids.size())});
    times.rows.push_back({r.name, fixed(r.prepare_ms, 3), describe, fixed(r.query_ms, 3)});
    if (defined) {
      curves.push_back(report::pr_series(pr.curve, r.name));
      std::vector<std::string> row = {r.name};
      for (std::string& c : direction_cells(r.by_direction)) row.push_back(std::move(c));
      direction.rows.push_back(std::move(row));
    }
  }
  const bool evaluated =
      std::any_of(runs.begin(), runs.end(), [](const MethodRun& r) { return r.evaluated; });
  if (evaluated && !any_revisits) {
    const std::string note =
        "no ground-truth revisits (" + protocol + "): AUC, recall and F1 are undefined (n/a)";
    std::printf("%s\n", note.c_str());
    page.paragraphs.push_back(note + ".");
    summary["note"] = note;
  }
  page.tables.push_back(places_table);
  if (any_revisits) page.tables.push_back(direction);
  page.tables.push_back(times);
  return curves;
}

}  // namespace loopscan::cli
