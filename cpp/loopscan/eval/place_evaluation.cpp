#include "loopscan/eval/place_evaluation.hpp"

#include <algorithm>
#include <chrono>

#include "loopscan/core/parallel.hpp"
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

  const int threads = std::max(1, std::min<int>(options.threads, static_cast<int>(queries.size())));
  out.matches.resize(queries.size());
  std::vector<double> thread_ms(threads, 0.0);
  const bool adaptive = options.fusion == Fusion::Adaptive && options.method != Method::Delight;
  // Adaptive fusion: the z-scored halves of every row first, then weights for the whole set.
  std::vector<Eigen::RowVectorXf> zs(adaptive ? queries.size() : 0), zi(zs.size());
  auto components_of = [&](std::size_t i, Eigen::MatrixXd& components) {
    const auto t0 = std::chrono::steady_clock::now();
    matcher->distances(queries[i], components);
    return t0;
  };
  if (adaptive) {
    run_on_threads(threads, [&](int t) {
      Eigen::MatrixXd components;
      for (std::size_t i = t; i < queries.size(); i += threads) {
        const auto t0 = components_of(i, components);
        Eigen::RowVectorXd s = components.row(0), g = components.row(1);
        row_zscore(s);
        row_zscore(g);
        zs[i] = s.cast<float>();
        zi[i] = g.cast<float>();
        thread_ms[t] += std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - t0).count();
      }
    });
    out.weights = adaptive_fusion_weights(zs, zi, options.protocol.mask_width,
                                          options.structure_weight);
  } else {
    out.weights.structure = options.structure_weight;
  }
  auto work = [&](int t) {
    Eigen::MatrixXd components;
    for (std::size_t i = t; i < queries.size(); i += threads) {
      Eigen::RowVectorXd row;
      if (adaptive) {
        row = (out.weights.structure * zs[i] + out.weights.intensity * zi[i]).cast<double>();
      } else {
        const auto t0 = components_of(i, components);
        row = combine_components(components, options.fusion, options.structure_weight);
        thread_ms[t] += std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - t0).count();
      }
      // The mask applies after fusion: the row statistics include the excluded columns.
      out.matches[i] = best_match(row.data(), static_cast<int>(row.size()), static_cast<int>(i),
                                  options.protocol.mask_width);
    }
  };
  run_on_threads(threads, work);
  double total_ms = 0;
  for (double ms : thread_ms) total_ms += ms;
  out.query_ms = queries.empty() ? 0.0 : total_ms / static_cast<double>(queries.size());
  out.pr = evaluate_matches(out.matches, query_positions, database_positions, options.protocol,
                            options.reference_quirks);
  return out;
}

}  // namespace loopscan::eval
