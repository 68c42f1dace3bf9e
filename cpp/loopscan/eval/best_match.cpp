#include "loopscan/eval/best_match.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace loopscan::eval {

QueryMatch best_match(const double* row, int n_db, int query_index, int mask_width) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  QueryMatch result{query_index, 0, kInf};
  if (n_db <= 0 || row == nullptr) return result;

  int best = -1;
  double best_value = kInf;
  for (int j = 0; j < n_db; ++j) {
    // The mask overrides the stored value, so a masked NaN becomes +inf, as in the reference.
    const double value = std::abs(query_index - j) < mask_width ? kInf : row[j];
    if (std::isnan(value)) continue;
    if (best < 0 || value < best_value) {
      best = j;
      best_value = value;
    }
  }
  if (best < 0) {
    result.distance = std::numeric_limits<double>::quiet_NaN();  // all-NaN row
  } else {
    result.match = best;
    result.distance = best_value;
  }
  return result;
}

}  // namespace loopscan::eval
