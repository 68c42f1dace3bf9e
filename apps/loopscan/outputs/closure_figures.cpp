#include "outputs/closure_figures.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unordered_map>

#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/report/plot.hpp"
#include "loopscan/report/trajectory_error.hpp"

namespace loopscan::cli {
namespace {

std::string format(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

// Trajectories before and after, aligned to the ground truth (or the closed one to the input
// frame without it); accepted loops as segments, false ones in red. With ground truth the
// closed trajectory is coloured by its APE and a second figure plots APE over distance.
ClosureFigures closure_figures(const ClosureRun& run, const std::optional<GroundTruth>& gt,
                               const std::vector<char>& loop_true) {
  const std::vector<Eigen::Vector3d> before = positions(run.input), after = positions(run.closed);
  std::vector<Eigen::Vector3d> reference = before;
  if (gt) {
    reference.clear();
    for (const KeyframePose& k : run.input) reference.push_back(gt->positions[std::size_t(k.id)]);
  }
  const Eigen::Isometry3d A = eval::rigid_alignment(reference, before);
  const Eigen::Isometry3d B = eval::rigid_alignment(reference, after);
  std::vector<Eigen::Vector3d> before_aligned, after_aligned;
  for (const Eigen::Vector3d& p : before) before_aligned.push_back(A * p);
  for (const Eigen::Vector3d& p : after) after_aligned.push_back(B * p);
  const std::pair<int, int> axes = report::top_view_axes(reference);
  const auto [ax, az] = axes;
  const auto series = [&axes](const std::string& name, const std::vector<Eigen::Vector3d>& p,
                              const std::string& color) {
    return report::top_view_series(name, p, axes, color);
  };
  std::unordered_map<int, std::size_t> at;
  for (std::size_t i = 0; i < run.closed.size(); ++i) at[run.closed[i].id] = i;
  report::Series good{"accepted loop", {}, {}, "#2ca02c"}, bad{"false loop", {}, {}, "#d62728"};
  good.width = bad.width = 1.0;
  for (std::size_t i = 0; i < run.loops.size(); ++i) {
    const closure::Loop& l = run.loops[i];
    if (!l.accepted() || !at.count(l.match.keyframe)) continue;
    report::Series& s = loop_true.empty() || loop_true[i] ? good : bad;
    for (int id : {l.query, l.match.keyframe}) {
      const Eigen::Vector3d& w = after_aligned[at[id]];
      s.x.push_back(w[ax]);
      s.y.push_back(w[az]);
    }
    s.x.push_back(NAN);
    s.y.push_back(NAN);
  }
  report::Series vo_before = series("VO (before)", before_aligned, "#b0b0b0");
  vo_before.width = 1.0;
  std::vector<report::Series> overlays;
  if (!good.x.empty()) overlays.push_back(good);
  if (!bad.x.empty()) overlays.push_back(bad);
  ClosureFigures f;
  if (!gt) {
    std::vector<report::Series> all = {vo_before,
                                       series("closed (after)", after_aligned, "#1f77b4")};
    all.insert(all.end(), overlays.begin(), overlays.end());
    f.map = report::map_plot_svg(all, "Trajectory before and after loop closing (no ground truth)",
                                 report::axis_label(ax), report::axis_label(az));
    return f;
  }
  report::TrajectoryFigure t;
  t.title = "Keyframes after loop closing";
  t.gt = reference;
  t.estimate = after_aligned;
  t.estimate_name = "closed (after)";
  t.underlays = {vo_before};
  t.overlays = overlays;
  f.map = report::trajectory_error_map_svg(t);
  f.error = report::error_over_distance_svg(
      "Position error along the drive, before and after loop closing (rigidly aligned)", reference,
      {{"VO (before)", before_aligned}, {"closed (after)", after_aligned}});
  return f;
}

// `run`'s report table of the loop-closing step.
report::Table closing_table(const nlohmann::json& m) {
  const nlohmann::json& l = m["loops"];
  report::Table t{
      "Loop closing (Scan Context; closure/ holds its files)",
      {"loops accepted", "false", "keyframe ATE before m", "after m", "ms per keyframe"},
      {}};
  const auto value = [&](const char* key) {
    return m.contains(key) ? format("%.3f", m[key].get<double>()) : std::string("n/a");
  };
  t.rows.push_back(
      {std::to_string(l["accepted"].get<int>()),
       l.contains("false_accepted") ? std::to_string(l["false_accepted"].get<int>()) : "n/a",
       value("ate_before_m"), value("ate_after_m"),
       format("%.2f", m["ms_per_keyframe"]["total"].get<double>())});
  return t;
}

}  // namespace loopscan::cli
