#pragma once
// The demo report: results of every method and the figures built from them.
#include <vector>

#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/eval/direction_split.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/report/html_page.hpp"
#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan::cli {

struct MethodResult {
  Method method = Method::ScanContext;
  eval::PlaceEvaluation same, cross;
  eval::DirectionSplit same_by_direction, cross_by_direction;
  std::vector<Eigen::Vector3d> map_positions;    // summer keyframes (the map, same-season queries)
  std::vector<Eigen::Vector3d> query_positions;  // cross-season queries (winter keyframes)
  double imitate_ms = 0, describe_ms = 0;
};

struct ExampleScan {
  int keyframe_id = -1;
  Cloud scan;  // camera frame, Cartesian-filtered
  Signature scan_context;
  ScanContextConfig config;  // what it was described with (rings, sectors, radius)
};

struct DemoResults {
  const sim::Trajectory* route = nullptr;
  int threads = 1;  // for describing and matching (the table's run times)
  Mode mode = Mode::Default;
  eval::Protocol same_season, cross_season;
  std::vector<MethodResult> methods;
  ExampleScan example;
  std::vector<report::Figure> opposite;  // one reverse revisit's scans (demo_opposite.hpp)
};

// The imitated scan and Scan Context of the keyframe in the middle of the session.
ExampleScan example_scan(const sim::VoOutput& vo, const SequenceOptions& options);

report::HtmlPage demo_page(const DemoResults& results);

}  // namespace loopscan::cli
