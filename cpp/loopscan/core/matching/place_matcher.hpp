#pragma once
// Exact difference-matrix rows: distances from a query place to every database place, for one
// descriptor, computed by a fast path tested against the pair distances of pair_distance.hpp.
#include <memory>
#include <vector>

#include "loopscan/core/config.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

// Float is the fast default; double reproduces the authors' Matlab to rounding.
enum class Precision { Float, Double };

class PlaceMatcher {
 public:
  virtual ~PlaceMatcher() = default;
  virtual void add(const Signature& place) = 0;
  virtual std::size_t size() const = 0;
  // Distance components: 2 for SC and M2DP (structure, intensity), 1 for DELIGHT and bird's-eye.
  virtual int components() const = 0;
  // rows(c, j) = component c of the distance from `query` to database place j.
  virtual void distances(const Signature& query, Eigen::MatrixXd& rows) const = 0;
  // The evaluation's rows for query `query_index`, which may match the columns j with
  // |query_index - j| >= mask_width: distances() for one-stage methods. Two-stage methods (the
  // bird's-eye place) rank those columns by the key distance of distances(), score the best
  // finalists exactly and set every other column to +inf.
  virtual void rows(const Signature& query, int /*query_index*/, int /*mask_width*/,
                    Eigen::MatrixXd& rows) const {
    distances(query, rows);
  }
};

std::unique_ptr<PlaceMatcher> make_matcher(Method method, Precision precision,
                                           const ScanContextConfig& sc = {});

std::unique_ptr<PlaceMatcher> make_scan_context_matcher(Precision precision,
                                                        const ScanContextConfig& config);
std::unique_ptr<PlaceMatcher> make_m2dp_matcher(Precision precision);
std::unique_ptr<PlaceMatcher> make_delight_matcher(Precision precision);
// Key distances (exact, float) in distances(); rows() searches the images of `finalists`.
std::unique_ptr<PlaceMatcher> make_birds_eye_matcher(const BirdsEyePlaceConfig& place = {},
                                                     const BirdsEyeSearchConfig& search = {});

}  // namespace loopscan
