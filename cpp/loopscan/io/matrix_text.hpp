#pragma once
// Numeric matrices as text, one row a line (the reference signature layout).
#include <cstddef>
#include <string>

#include <Eigen/Core>

#include "loopscan/io/limits.hpp"

namespace loopscan::io {

// Whitespace-separated numbers, one row a line; .gz is supported. expected_cols = 0 accepts any
// width as long as every row has the width of the first. Rows of the wrong width or junk tokens
// throw InputError naming the line and "N numbers". Blank lines only at the end; an empty file
// gives a 0 x expected_cols matrix. Every value must be finite and within +-max_abs (default:
// what single precision holds with room).
Eigen::MatrixXd read_matrix_text(const std::string& path, std::size_t expected_cols = 0,
                                 double max_abs = limits::kMaxSignatureValue);

// Writes each value with `significant_digits` significant digits (printf "%.*g" formatting,
// 1..17; 0 selects the shortest text that round-trips exactly), single spaces, '\n' per row.
// Atomic; gzip-compressed when `path` ends in ".gz". Other digit counts throw
// std::invalid_argument.
void write_matrix_text(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m,
                       int significant_digits = 10);

// The values read_matrix_text returns for what write_matrix_text writes with the same digits:
// code that prints numbers and writes the signatures computes them from these, so that a
// `describe` + `evaluate` of its files gives the same digits.
Eigen::MatrixXd as_written(const Eigen::Ref<const Eigen::MatrixXd>& m, int significant_digits = 10);

}  // namespace loopscan::io
