#pragma once
// What `close`, `slam`, `run` and `demo` show of a loop-closing run: the trajectory figure and
// the report table.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/report/html_page.hpp"
#include "outputs/closure.hpp"

namespace loopscan::cli {

// Trajectories before and after, aligned to the ground truth (without it, to the input's
// frame), accepted loops as segments, false ones (loop_true[i] == 0) in red; with ground truth
// evo-style: the closed trajectory coloured by its error, and the error over distance.
ClosureFigures closure_figures(const ClosureRun& run, const std::optional<GroundTruth>& gt,
                               const std::vector<char>& loop_true);

// `run`'s report table of the loop-closing step (metrics.json's content).
report::Table closing_table(const nlohmann::json& metrics);

}  // namespace loopscan::cli
