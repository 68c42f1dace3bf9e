#include "loopscan/eval/place_evaluation.hpp"

#include <algorithm>
#include <chrono>

#include "loopscan/core/parallel.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/eval/best_match.hpp"

namespace loopscan::eval {

PlaceEvaluationOptions PlaceEvaluationOptions::make(Method method, Mode mode) {
  PlaceEvaluationOptions o;
  o.method = method;
  o.fusion = default_fusion(mode);
  o.precision = mode == Mode::Reference ? Precision::Double : Precision::Float;
  o.reference_quirks = mode == Mode::Reference;
  return o;
}

PlaceEvaluation evaluate_places(const std::vector<Signature>& queries,
                                const std::vector<Signature>& database,
                                const std::vector<Eigen::Vector3d>& query_positions,
                                const std::vector<Eigen::Vector3d>& database_positions,
                                const PlaceEvaluationOptions& options) {
  PlaceEvaluation out;
  const auto matcher = options.method == Method::BirdsEye
                           ? make_birds_eye_matcher(options.birds_eye, options.birds_eye_search)
                           : make_matcher(options.method, options.precision);
  for (const Signature& place : database) matcher->add(place);

  const int threads = std::max(1, std::min<int>(options.threads, static_cast<int>(queries.size())));
  out.matches.resize(queries.size());
  std::vector<double> thread_ms(threads, 0.0);
  const bool adaptive = options.two_passes();
  const int mask = options.protocol.mask_width;
  const std::size_t passes = adaptive ? 2 : 1, rows = passes * queries.size();
  auto report = [&](int t, std::size_t pass, std::size_t i) {
    const std::size_t in_pass = std::min(i + threads, queries.size());
    report_worker_progress(options.progress, t, pass * queries.size() + in_pass, rows);
  };
  out.weights.structure = options.structure_weight;
  if (adaptive) {  // pass one: the statistics of the whole difference matrix
    std::vector<FusionStatistics> stats(threads);
    run_on_threads(threads, [&](int t) {
      Eigen::MatrixXd components;
      for (std::size_t i = t; i < queries.size(); i += threads) {
        const auto t0 = std::chrono::steady_clock::now();
        matcher->distances(queries[i], components);
        stats[t].add_row(components.row(0), components.row(1), static_cast<int>(i), mask);
        thread_ms[t] += ms_since(t0);
        report(t, 0, i);
      }
    });
    for (int t = 1; t < threads; ++t) stats[0].merge(stats[t]);
    out.weights = stats[0].weights(options.structure_weight);
  }
  auto work = [&](int t) {
    Eigen::MatrixXd components;
    for (std::size_t i = t; i < queries.size(); i += threads) {
      const auto t0 = std::chrono::steady_clock::now();
      matcher->rows(queries[i], static_cast<int>(i), mask, components);
      const Eigen::RowVectorXd row =
          adaptive ? adaptive_fused_row(components.row(0), components.row(1), out.weights)
                   : combine_components(components, options.fusion, options.structure_weight);
      thread_ms[t] += ms_since(t0);
      // The mask applies after fusion: the row statistics include the excluded columns.
      out.matches[i] =
          best_match(row.data(), static_cast<int>(row.size()), static_cast<int>(i), mask);
      report(t, passes - 1, i);
    }
  };
  run_on_threads(threads, work);
  report_progress(options.progress, rows, rows);
  double total_ms = 0;
  for (double ms : thread_ms) total_ms += ms;
  out.query_ms = queries.empty() ? 0.0 : total_ms / static_cast<double>(queries.size());
  out.pr = evaluate_matches(out.matches, query_positions, database_positions, options.protocol,
                            options.reference_quirks);
  return out;
}

}  // namespace loopscan::eval
