#include "loopscan/eval/place_evaluation.hpp"

#include <chrono>

#include "loopscan/eval/best_match.hpp"

namespace loopscan::eval {

PlaceEvaluation evaluate_places(const std::vector<Signature>& queries,
                                const std::vector<Signature>& database,
                                const std::vector<Eigen::Vector3d>& query_positions,
                                const std::vector<Eigen::Vector3d>& database_positions,
                                const PlaceEvaluationOptions& options) {
  PlaceEvaluation out;
  const auto matcher = make_matcher(options.method, options.precision);
  for (const Signature& place : database) matcher->add(place);

  Eigen::MatrixXd components;
  double total_ms = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    matcher->distances(queries[i], components);
    const Eigen::RowVectorXd row =
        combine_components(components, options.fusion, options.structure_weight);
    total_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // The mask applies after fusion: the row statistics include the excluded columns.
    out.matches.push_back(best_match(row.data(), static_cast<int>(row.size()), static_cast<int>(i),
                                     options.protocol.mask_width));
  }
  out.query_ms = queries.empty() ? 0.0 : total_ms / static_cast<double>(queries.size());
  out.pr = evaluate_matches(out.matches, query_positions, database_positions, options.protocol,
                            options.reference_quirks);
  return out;
}

}  // namespace loopscan::eval
