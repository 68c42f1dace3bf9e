#pragma once
// Per-query prediction: arg-min of one row of the difference matrix, Matlab min() semantics.

namespace loopscan::eval {

struct QueryMatch {
  int query = 0;
  int match = 0;
  double distance = 0.0;
};

// row: distances from query `query_index` to every db entry (length n_db), already normalised
// by the caller. Columns with |query_index - j| < mask_width count as +inf. Ties -> first
// index. NaN entries are skipped like Matlab's min; an all-NaN row gives {0, NaN}. When every
// column is excluded (or n_db == 0) the result is {0, +inf}, as Matlab returns index 1.
QueryMatch best_match(const double* row, int n_db, int query_index, int mask_width);

}  // namespace loopscan::eval
