// loopscan demo: the built-in city in summer and in winter, the three descriptors same-season
// and cross-season, and an HTML report with figures. No download needed.
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iterator>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "demo/figures.hpp"
#include "demo/opposite.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/report/pr_plot.hpp"
#include "outputs/closure.hpp"
#include "outputs/closure_figures.hpp"
#include "outputs/evaluation.hpp"
#include "outputs/reproduce_script.hpp"
#include "outputs/signatures.hpp"
#include "outputs/simulation.hpp"

namespace loopscan::cli {
namespace {

struct DemoArgs {
  ConfigFlags config;
  std::string out = "demo";
  std::string trajectory = "builtin:city";
  unsigned seed = 7;
  int threads = 2;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Every figure of the page also as its own SVG file (`NN-caption-words.svg`), for documents.
void write_figure_files(const report::HtmlPage& page, const std::string& dir) {
  std::filesystem::create_directories(dir);
  for (std::size_t k = 0; k < page.figures.size(); ++k) {
    std::string name = (k < 9 ? "0" : "") + std::to_string(k + 1) + "-";
    for (char c : page.figures[k].caption) {
      if (name.size() >= 40) break;
      const bool word = std::isalnum(static_cast<unsigned char>(c)) != 0;
      if (word)
        name += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      else if (name.back() != '-')
        name += '-';
    }
    while (name.back() == '-') name.pop_back();
    io::write_file_atomic(dir + "/" + name + ".svg", page.figures[k].svg);
  }
}

std::string format(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

struct DemoClosing {
  report::Table table;
  std::vector<report::Figure> figures;
  std::string summary;  // one line for the terminal
};

// The demo's loop closing: the summer drive closed on its own (files in out/closure-summer),
// then the winter drive against the summer map (out/closure-winter); ground truth from `route`.
DemoClosing close_demo_sessions(const std::string& out, const LoadedTrajectory& route,
                                const std::vector<Session>& sessions, const Configuration& c) {
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
  closure::LoopCloserConfig config = loop_closer_config(c);
  SavedMap map;
  const char* names[2] = {"summer", "winter (in the summer map)"};
  for (std::size_t i = 0; i < 2 && i < sessions.size(); ++i) {
    config.recognition.session = int(i);
    const std::string dir = out + (i == 0 ? "/closure-summer" : "/closure-winter");
    std::filesystem::create_directories(dir);
    ClosureRun run =
        run_closer(config, sessions[i].vo.poses, points_in_memory(sessions[i].vo.points), {}, true,
                   closure_queue(c), i == 0 ? nullptr : &map);
    const ClosureOutputs outputs = write_closure_outputs(dir, run, c, gt, {});
    const nlohmann::json& m = outputs.metrics;
    d.figures.push_back({std::string("Loop closing, ") + names[i], outputs.figures.map});
    if (!outputs.figures.error.empty())
      d.figures.push_back({std::string("Position error, ") + names[i], outputs.figures.error});
    const nlohmann::json& l = m["loops"];
    d.table.rows.push_back({names[i], std::to_string(l["accepted"].get<int>()),
                            std::to_string(l["false_accepted"].get<int>()),
                            format("%.3f", m["ate_before_m"].get<double>()),
                            format("%.3f", m["ate_after_m"].get<double>()),
                            format("%.2f", m["ms_per_keyframe"]["total"].get<double>())});
    d.summary += std::string(i ? "; " : "") + names[i] + " " +
                 std::to_string(l["accepted"].get<int>()) + " loops (" +
                 std::to_string(l["false_accepted"].get<int>()) + " false), ATE " +
                 format("%.2f", m["ate_before_m"].get<double>()) + " -> " +
                 format("%.2f", m["ate_after_m"].get<double>()) + " m";
    map.places = std::move(run.map);
    map.clouds = std::move(run.clouds);
  }
  return d;
}


void run_demo(const DemoArgs& a) {
  const auto t_start = std::chrono::steady_clock::now();
  // Every method is described and evaluated; loops close with Scan Context (a method the file
  // names is not used).
  Configuration c = resolve_configuration(a.config);
  c.method = Method::ScanContext;
  c.image_baseline.reset();
  require_loop_closing(c, a.config);
  // One numbered line per step; each part then ends with its own time (progress.hpp).
  constexpr Method kMethods[] = {Method::ScanContext, Method::M2dp, Method::Delight};
  // Steps: world, the two drives, one per method, loop closing, report.
  StepCounter steps(1 + 2 + static_cast<int>(std::size(kMethods)) + 2);
  steps.next("route and world");
  StepProgress world_time("  world", "objects");
  const LoadedTrajectory route = load_trajectory(a.trajectory, c.simulator.world);
  sim::WorldConfig wc = c.simulator.world;
  wc.seed = a.seed;
  const sim::World world = sim::World::build(route.trajectory.centres(), wc);
  const sim::StereoCamera camera;
  world_time.update(world.object_count(), world.object_count());
  world_time.finish();

  std::vector<Session> sessions;
  const char* names[2] = {"summer", "winter"};
  for (int i = 0; i < 2; ++i) {
    steps.next(std::string("the ") + names[i] + " drive: simulated stereo VO");
    sim::Conditions conditions = simulated_conditions(c, sim::parse_season(names[i]));
    conditions.session_seed = 100 + i;
    sim::VoSimConfig vo = c.simulator.vo;
    vo.seed = conditions.noise_seed(a.seed);
    sessions.push_back(with_progress("  simulate", "keyframes", false, vo.progress, [&] {
      return simulate_session(route, world, conditions, camera, vo, {});
    }));
    write_session(a.out + "/" + names[i], route, sessions.back());
    // From here on the session is its files: `describe` + `evaluate` on them recompute the table.
    reload_session(a.out + "/" + names[i], route, sessions.back());
  }

  DemoResults results;
  results.route = &route.trajectory;
  results.threads = a.threads;
  results.mode = c.mode;
  results.same_season = c.evaluation.same_session;
  results.cross_season = c.evaluation.cross_session;
  for (Method method : kMethods) {
    steps.next(method_name(method) +
               ": describe both drives, then match summer against itself and "
               "winter against summer");
    MethodResult mr;
    mr.method = method;
    SequenceOptions options = sequence_options(c, method);
    options.threads = a.threads;
    SequenceSignatures sig[2];
    std::vector<Eigen::Vector3d> pos[2];
    for (int i = 0; i < 2; ++i) {
      sig[i] = with_progress(
          std::string("  describe ") + names[i], "keyframes", false, options.progress, [&] {
            return describe_as_written(sessions[i].vo.poses, sessions[i].vo.points, options, c);
          });
      for (int id : sig[i].keyframe_ids) pos[i].push_back(sessions[i].gt_positions[id]);
    }
    mr.imitate_ms = sig[0].imitate_ms;
    mr.describe_ms = sig[0].describe_ms;
    eval::PlaceEvaluationOptions eo = place_evaluation_options(c, method, false);
    eo.threads = a.threads;
    mr.same = with_progress("  match summer vs summer", "rows", false, eo.progress, [&] {
      return eval::evaluate_places(sig[0].signatures, sig[0].signatures, pos[0], pos[0], eo);
    });
    eo.protocol = c.evaluation.cross_session;
    mr.cross = with_progress("  match winter vs summer", "rows", false, eo.progress, [&] {
      return eval::evaluate_places(sig[1].signatures, sig[0].signatures, pos[1], pos[0], eo);
    });
    mr.map_positions = pos[0];
    mr.query_positions = pos[1];
    std::vector<Eigen::Vector3d> heading[2];
    for (int i = 0; i < 2; ++i)
      for (int id : sig[i].keyframe_ids) heading[i].push_back(sessions[i].gt_headings[id]);
    mr.same_by_direction = eval::split_by_direction(mr.same.pr, pos[0], pos[0], heading[0],
                                                    heading[0], c.evaluation.same_session);
    mr.cross_by_direction = eval::split_by_direction(mr.cross.pr, pos[1], pos[0], heading[1],
                                                     heading[0], c.evaluation.cross_session);
    if (method == Method::ScanContext) {
      results.opposite = opposite_figures(route.trajectory, sessions[0].vo,
                                          opposite_revisit(route.trajectory, sig[0].keyframe_ids));
    }
    if (method == Method::ScanContext) results.example = example_scan(sessions[0].vo, options);
    results.methods.push_back(mr);
  }

  steps.next("loop closing: the summer drive, then the winter drive in the summer map");
  const DemoClosing closing = close_demo_sessions(a.out, route, sessions, c);
  steps.next("report");
  const std::vector<report::Figure> bev_revisit =
      birds_eye_revisit_figures(route.trajectory, sessions[0].vo, c, a.threads);
  results.opposite.insert(results.opposite.end(), bev_revisit.begin(), bev_revisit.end());
  std::printf("\n%-8s | %-26s | %-26s | %9s %9s %9s\n", "", "summer vs summer", "winter vs summer",
              "imitate", "describe", "query");
  std::printf("%-8s | %8s %8s %8s | %8s %8s %8s | %9s %9s %9s\n", "method", "AUC", "R@100P",
              "F1max", "AUC", "R@100P", "F1max", "ms/kf", "ms/kf", "ms/query");
  nlohmann::json table = nlohmann::json::array();
  for (const MethodResult& m : results.methods) {
    std::printf("%-8s | %8.4f %8.4f %8.4f | %8.4f %8.4f %8.4f | %9.3f %9.3f %9.3f\n",
                method_name(m.method).c_str(), m.same.pr.auc, m.same.pr.recall_at_100_precision,
                m.same.pr.f1_max, m.cross.pr.auc, m.cross.pr.recall_at_100_precision,
                m.cross.pr.f1_max, m.imitate_ms, m.describe_ms, m.same.query_ms);
    table.push_back({{"method", method_name(m.method)},
                     {"same_season",
                      {{"auc", m.same.pr.auc},
                       {"recall_at_100_precision", m.same.pr.recall_at_100_precision},
                       {"f1_max", m.same.pr.f1_max},
                       {"n_gt_loops", m.same.pr.n_gt_loops}}},
                     {"cross_season",
                      {{"auc", m.cross.pr.auc},
                       {"recall_at_100_precision", m.cross.pr.recall_at_100_precision},
                       {"f1_max", m.cross.pr.f1_max},
                       {"n_gt_loops", m.cross.pr.n_gt_loops}}},
                     {"same_season_by_direction", direction_metrics(m.same_by_direction)},
                     {"cross_season_by_direction", direction_metrics(m.cross_by_direction)},
                     {"imitate_ms", m.imitate_ms},
                     {"describe_ms", m.describe_ms},
                     {"query_ms", m.same.query_ms}});
  }
  std::filesystem::create_directories(a.out + "/report");
  io::write_file_atomic(a.out + "/report/metrics.json", table.dump(1) + "\n");
  report::HtmlPage page = demo_page(results);
  page.tables.push_back(closing.table);
  page.figures.insert(page.figures.end(), closing.figures.begin(), closing.figures.end());
  io::write_file_atomic(a.out + "/report/index.html", report::render_html(page));
  write_figure_files(page, a.out + "/report/figures");
  write_used_configuration(a.out, c, false);
  write_reproduce_script(a.out + "/report/reproduce.sh", demo_script(a.threads));
  std::printf("\nloop closing: %s\n", closing.summary.c_str());
  std::printf("recompute the table from the written files: sh %s\n",
              shown(a.out + "/report/reproduce.sh").c_str());
  std::printf("\n%zu / %zu keyframes, %.0f points per keyframe; finished in %.0f s -> %s\n",
              sessions[0].keyframe_ids.size(), sessions[1].keyframe_ids.size(),
              sessions[0].vo.mean_points_per_keyframe, seconds_since(t_start),
              shown(a.out + "/report/index.html").c_str());
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Simulate the built-in city in summer and winter, run all descriptors, report");
  cmd->add_option("--out", args->out, "output directory")->capture_default_str();
  cmd->add_option("--seed", args->seed, "world seed")->capture_default_str();
  cmd->add_option("--trajectory", args->trajectory,
                  "route: builtin:city, builtin:short (a quick look), builtin:reverse, kitti:FILE, "
                  "robotcar:FILE")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "threads for description and matching")
      ->check(finite_in(1, kMaxThreads))
      ->capture_default_str();
  add_config_option(*cmd, args->config);
  run_writing_dir(cmd, args, run_demo);
}

}  // namespace loopscan::cli
