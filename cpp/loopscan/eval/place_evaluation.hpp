#pragma once
// The paper's place-recognition evaluation end to end: difference-matrix rows from a fast
// matcher, fusion, mask, per-query best match, PR curve and metrics.
#include <vector>

#include "loopscan/core/matching/adaptive_fusion.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/progress.hpp"
#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/eval/protocol.hpp"

namespace loopscan::eval {

struct PlaceEvaluationOptions {
  Method method = Method::ScanContext;
  Fusion fusion = Fusion::Fused;
  double structure_weight = 2.0;  // w_s
  Precision precision = Precision::Float;
  Protocol protocol = same_session_protocol();
  bool reference_quirks = false;
  int threads = 1;  // queries split over threads; results identical
  // Bird's-eye places: the layout the signatures were described with, and the image search.
  BirdsEyePlaceConfig birds_eye;
  BirdsEyeSearchConfig birds_eye_search;
  // (rows computed, rows to compute), from the calling thread; adaptive fusion counts its two
  // passes over the queries.
  ProgressFn progress;
  // The mode's evaluation: its default fusion; reference mode in double precision with the
  // Matlab quirks, as the authors' numbers were made.
  static PlaceEvaluationOptions make(Method method, Mode mode);
  // Adaptive fusion needs the whole matrix's statistics first: two passes over the queries.
  bool two_passes() const {
    return fusion == Fusion::Adaptive && distance_components(method) == 2;
  }
};

struct PlaceEvaluation {
  std::vector<QueryMatch> matches;  // one per query
  PrResult pr;
  FusionWeights weights;  // the weights used (adaptive: chosen for this pair of sets)
  // Mean time of one difference-matrix row (all components, fused), per thread; adaptive
  // fusion computes every row twice (statistics, then fusion) and counts both.
  double query_ms = 0;
};

PlaceEvaluation evaluate_places(const std::vector<Signature>& queries,
                                const std::vector<Signature>& database,
                                const std::vector<Eigen::Vector3d>& query_positions,
                                const std::vector<Eigen::Vector3d>& database_positions,
                                const PlaceEvaluationOptions& options);

}  // namespace loopscan::eval
