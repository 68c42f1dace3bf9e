#pragma once
// The files `evaluate` and `db query` write for an evaluation: metrics.json, pr.csv,
// matches.csv (query id, matched id, distance, is_true) and pr.svg.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/eval/direction_split.hpp"
#include "loopscan/eval/precision_recall.hpp"

namespace loopscan::cli {

// auc, recall_at_100_precision, f1_max, n_queries, n_gt_loops of a PR result.
nlohmann::json pr_metrics(const eval::PrResult& pr);

// {"same": {...}, "opposite": {...}}: pr_metrics plus n_loops and top1_correct per class.
nlohmann::json direction_metrics(const eval::DirectionSplit& split);
// One line per class on stdout.
void print_direction_split(const eval::DirectionSplit& split);
// Report cells: "top-1 correct / loops" and AUC, same direction then opposite.
std::vector<std::string> direction_cells(const eval::DirectionSplit& split);
// A report cell: `x` with `digits` decimals.
std::string fixed(double x, int digits);
// "10 m, |i - j| >= 100" or "25 m, no mask": a protocol in a report's words.
std::string protocol_text(const eval::Protocol& protocol);

// query_ids / db_ids: keyframe ids behind the match indices of `pr`.
void write_evaluation(const std::string& dir, const std::vector<int>& query_ids,
                      const std::vector<int>& db_ids, const eval::PrResult& pr,
                      const nlohmann::json& metrics, const std::string& title);

}  // namespace loopscan::cli
