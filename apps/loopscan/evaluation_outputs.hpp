#pragma once
// The files `evaluate` and `db query` write for an evaluation: metrics.json, pr.csv,
// matches.csv (query id, matched id, distance, is_true) and pr.svg.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/eval/precision_recall.hpp"

namespace loopscan::cli {

// query_ids / db_ids: keyframe ids behind the match indices of `pr`.
void write_evaluation(const std::string& dir, const std::vector<int>& query_ids,
                      const std::vector<int>& db_ids, const eval::PrResult& pr,
                      const nlohmann::json& metrics, const std::string& title);

}  // namespace loopscan::cli
