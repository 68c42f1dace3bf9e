#include "closure_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unordered_map>

#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/report/plot.hpp"

namespace loopscan::cli {
namespace {

std::string format(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

// Trajectories before and after, aligned to the ground truth (or the closed one to the input
// frame without it); accepted loops as segments, false ones in red.
std::string closure_trajectory_svg(const ClosureRun& run, const std::optional<GroundTruth>& gt,
                              const std::vector<char>& loop_true) {
  const std::vector<Eigen::Vector3d> before = positions(run.input), after = positions(run.closed);
  std::vector<Eigen::Vector3d> reference = before;
  if (gt) {
    reference.clear();
    for (const KeyframePose& k : run.input) reference.push_back(gt->positions[std::size_t(k.id)]);
  }
  const Eigen::Isometry3d A = eval::rigid_alignment(reference, before);
  const Eigen::Isometry3d B = eval::rigid_alignment(reference, after);
  // Top view: the two axes of largest spread of the reference.
  Eigen::Vector3d lo = reference.empty() ? Eigen::Vector3d::Zero() : reference[0], hi = lo;
  for (const Eigen::Vector3d& p : reference) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d spread = hi - lo;
  int ax = 0, az = 2;
  if (spread[1] > spread[0] && spread[1] > spread[2]) ax = 1;  // e.g. RobotCar's north-east-down
  if (ax == 1 || spread[0] < spread[2]) az = ax == 0 ? 2 : (spread[0] > spread[2] ? 0 : 2);
  const auto series = [&](const std::string& name, const std::vector<Eigen::Vector3d>& p,
                          const Eigen::Isometry3d& T, const std::string& color) {
    report::Series s{name, {}, {}, color};
    for (const Eigen::Vector3d& v : p) {
      const Eigen::Vector3d w = T * v;
      s.x.push_back(w[ax]);
      s.y.push_back(w[az]);
    }
    return s;
  };
  std::vector<report::Series> all;
  if (gt) all.push_back(series("ground truth", reference, Eigen::Isometry3d::Identity(), "#222222"));
  all.push_back(series("VO (before)", before, A, "#999999"));
  all.push_back(series("closed (after)", after, B, "#1f77b4"));
  std::unordered_map<int, std::size_t> at;
  for (std::size_t i = 0; i < run.closed.size(); ++i) at[run.closed[i].id] = i;
  report::Series good{"accepted loops", {}, {}, "#2ca02c"}, bad{"false loops", {}, {}, "#d62728"};
  for (std::size_t i = 0; i < run.loops.size(); ++i) {
    const closure::Loop& l = run.loops[i];
    if (!l.accepted() || !at.count(l.match.keyframe)) continue;
    report::Series& s = loop_true.empty() || loop_true[i] ? good : bad;
    for (int id : {l.query, l.match.keyframe}) {
      const Eigen::Vector3d w = B * after[at[id]];
      s.x.push_back(w[ax]);
      s.y.push_back(w[az]);
    }
    s.x.push_back(NAN);
    s.y.push_back(NAN);
  }
  if (!good.x.empty()) all.push_back(good);
  if (!bad.x.empty()) all.push_back(bad);
  const char* axis[] = {"x [m]", "y [m]", "z [m]"};
  return report::map_plot_svg(all, "Trajectory before and after loop closing", axis[ax], axis[az]);
}


// `run`'s report table of the loop-closing step.
report::Table closing_table(const nlohmann::json& m) {
  const nlohmann::json& l = m["loops"];
  report::Table t{"Loop closing (Scan Context; closure/ holds its files)",
                  {"loops accepted", "false", "keyframe ATE before m", "after m", "ms per keyframe"},
                  {}};
  const auto value = [&](const char* key) {
    return m.contains(key) ? format("%.3f", m[key].get<double>()) : std::string("n/a");
  };
  t.rows.push_back({std::to_string(l["accepted"].get<int>()),
                    l.contains("false_accepted") ? std::to_string(l["false_accepted"].get<int>()) : "n/a",
                    value("ate_before_m"), value("ate_after_m"),
                    format("%.2f", m["ms_per_keyframe"]["total"].get<double>())});
  return t;
}

DemoClosing close_demo_sessions(const std::string& out, const LoadedTrajectory& route,
                                const std::vector<Session>& sessions) {
  GroundTruth gt;
  gt.path = "builtin:city";
  for (const Eigen::Isometry3d& T : route.trajectory.T_world_cam) {
    gt.poses.push_back(T.matrix().topRows<3>());
    gt.positions.push_back(T.translation());
  }
  DemoClosing d;
  d.table = {"Loop closing (Scan Context, verified by ICP, pose graph; keyframe ATE in m)",
             {"drive", "loops accepted", "false", "ATE before", "ATE after", "ms per keyframe"},
             {}};
  closure::LoopCloserConfig config = closure::LoopCloserConfig::make(Method::ScanContext);
  SavedMap map;
  const char* names[2] = {"summer", "winter (in the summer map)"};
  for (std::size_t i = 0; i < 2 && i < sessions.size(); ++i) {
    config.recognition.session = int(i);
    const std::string dir = out + (i == 0 ? "/closure-summer" : "/closure-winter");
    std::filesystem::create_directories(dir);
    ClosureRun run = run_closer(config, sessions[i].vo.poses, sessions[i].vo.points, {}, false,
                                i == 0 ? nullptr : &map);
    nlohmann::json m = write_closure_outputs(dir, run, config, gt, {}, 10.0);
    d.figures.push_back({std::string("Loop closing, ") + names[i], m["figure_svg"].get<std::string>()});
    const nlohmann::json& l = m["loops"];
    d.table.rows.push_back({names[i], std::to_string(l["accepted"].get<int>()),
                            std::to_string(l["false_accepted"].get<int>()),
                            format("%.3f", m["ate_before_m"].get<double>()),
                            format("%.3f", m["ate_after_m"].get<double>()),
                            format("%.2f", m["ms_per_keyframe"]["total"].get<double>())});
    d.summary += std::string(i ? "; " : "") + names[i] + " " + std::to_string(l["accepted"].get<int>()) +
                 " loops (" + std::to_string(l["false_accepted"].get<int>()) + " false), ATE " +
                 format("%.2f", m["ate_before_m"].get<double>()) + " -> " +
                 format("%.2f", m["ate_after_m"].get<double>()) + " m";
    map.places = std::move(run.map);
    map.clouds = std::move(run.clouds);
  }
  return d;
}

}  // namespace loopscan::cli
