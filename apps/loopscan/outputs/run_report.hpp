#pragma once
// `loopscan run`: each method's evaluation files and its rows of the report and summary.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/core/types.hpp"
#include "loopscan/eval/direction_split.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/report/plot.hpp"
#include "outputs/vo.hpp"

namespace loopscan::cli {

// One method's outcome, LiDAR-style (from the VO's points) or image baseline (left images).
struct MethodRun {
  std::string name;
  std::vector<int> keyframe_ids;  // the places
  eval::PrResult pr;
  eval::DirectionSplit by_direction;  // same- vs opposite-direction revisits
  bool evaluated = false;
  double prepare_ms = 0;          // imitate (LiDAR-style) / ORB or GIST extraction (images)
  double describe_ms = 0;         // describe / BoW transform
  bool has_describe_step = true;  // GIST's extraction is its whole description
  double query_ms = 0;
  eval::Protocol protocol = eval::same_session_protocol();  // what pr and by_direction used
};

// metrics.json (with by_direction), pr.csv, matches.csv, pr.svg of one method.
void write_method_evaluation(const MethodRun& r, const std::string& dir, Mode mode);

// evo-style VO figures: the trajectory coloured by its error against `gt` (one position per
// trajectory entry; empty: the VO alone) and that error over the distance travelled.
std::vector<report::Figure> trajectory_figures(const VoResult& vo,
                                               const std::vector<Eigen::Vector3d>& gt);

// The paper's route figure of one evaluated method: places recognised at 100 % precision and
// the place each matched; positions = ground truth per frame id.
report::Figure recognition_figure(const MethodRun& r,
                                  const std::vector<Eigen::Vector3d>& positions);

// Prints the console table and adds every method's rows to the page (accuracy, by direction,
// run time) and to summary["methods"]; returns the PR curves of the evaluated methods.
std::vector<report::Series> add_method_results(const std::vector<MethodRun>& runs, int threads,
                                               report::HtmlPage& page, nlohmann::json& summary);

}  // namespace loopscan::cli
