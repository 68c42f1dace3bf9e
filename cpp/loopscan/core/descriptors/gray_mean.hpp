#pragma once
// Mean gray value of a cloud: the threshold of the binarized intensity signatures.
#include "loopscan/core/types.hpp"

namespace loopscan {

// Reference mode accumulates in float, in cloud order, exactly like the authors' code (their
// bin/threshold comparisons depend on that rounding); default mode accumulates in double.
// Empty cloud: 0.
double cloud_gray_mean(const Cloud& cloud, Mode mode);

}  // namespace loopscan
