#pragma once
// A place signature in the authors' text layout, one matrix per place:
//   Scan Context: 1 x 2SR   [structure (S*R) | intensity (S*R)], index = sector * R + ring
//   M2DP:         4 x 2(pq + ab)  one row per PCA sign version, [count u|v | intensity u|v]
//   DELIGHT:      16 x bins   one row (gray histogram) per region
//   bird's-eye:   1 x (side^2 + rings * angles)   [image 0..255 | key -127..127]
#include <string>

#include "loopscan/core/types.hpp"

namespace loopscan {

using Signature = Eigen::MatrixXd;

// Rows each place occupies in a signature file, and their width, for the default parameters.
int rows_per_place(Method method);
int signature_columns(Method method);

// Distance components a method's places are compared by: 2 (structure, intensity) for Scan
// Context and M2DP, 1 for DELIGHT (intensity) and the bird's-eye place (structure).
inline int distance_components(Method method) {
  return method == Method::ScanContext || method == Method::M2dp ? 2 : 1;
}

// "sc" | "m2dp" | "delight" | "bev"; parse throws std::invalid_argument on anything else.
std::string method_name(Method method);
Method parse_method(const std::string& name);

// "reference" | "default"; parse throws std::invalid_argument on anything else.
std::string mode_name(Mode mode);
Mode parse_mode(const std::string& name);

}  // namespace loopscan
