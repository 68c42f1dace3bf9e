#pragma once
// What `close`, `slam` and `run` show of a loop-closing run: the trajectory figure and the
// report table.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "closure_outputs.hpp"
#include "loopscan/report/html_page.hpp"
#include "simulation_setup.hpp"

namespace loopscan::cli {

// Trajectories before and after, aligned to the ground truth (without it, to the input's
// frame), accepted loops as segments, false ones (loop_true[i] == 0) in red; with ground truth
// evo-style: the closed trajectory coloured by its error, and the error over distance.
ClosureFigures closure_figures(const ClosureRun& run, const std::optional<GroundTruth>& gt,
                               const std::vector<char>& loop_true);

// `run`'s report table of the loop-closing step (metrics.json's content).
report::Table closing_table(const nlohmann::json& metrics);

struct DemoClosing {
  report::Table table;
  std::vector<report::Figure> figures;
  std::string summary;  // one line for the terminal
};

// The demo's loop closing: the summer drive closed on its own (files in out/closure-summer),
// then the winter drive against the summer map (out/closure-winter); ground truth from `route`.
DemoClosing close_demo_sessions(const std::string& out, const LoadedTrajectory& route,
                                const std::vector<Session>& sessions);

}  // namespace loopscan::cli
