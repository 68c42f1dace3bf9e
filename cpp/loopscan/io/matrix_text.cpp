#include <loopscan/io/matrix_text.hpp>

#include <charconv>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/line_reader.hpp>
#include <loopscan/io/parse_numbers.hpp>
#include <loopscan/io/text_file_writer.hpp>

namespace loopscan::io {
namespace {

std::string numbers_expected(std::size_t cols) { return std::to_string(cols) + " numbers"; }

void check_digits(int significant_digits) {
  if (significant_digits < 0 || significant_digits > 17) {
    throw std::invalid_argument("write_matrix_text: significant_digits must be in [0, 17], got " +
                                std::to_string(significant_digits));
  }
}

// One number as write_matrix_text formats it; returns the end of the text.
char* format_number(char* first, char* last, double v, int significant_digits) {
  return (significant_digits == 0
              ? std::to_chars(first, last, v)
              : std::to_chars(first, last, v, std::chars_format::general, significant_digits))
      .ptr;
}

}  // namespace

Eigen::MatrixXd read_matrix_text(const std::string& path, std::size_t expected_cols,
                                 double max_abs) {
  LineReader reader(path);
  std::vector<double> values;
  std::size_t cols = expected_cols;
  std::size_t rows = 0;
  std::string expected = expected_cols > 0 ? numbers_expected(expected_cols) : "numbers";
  std::string_view line;
  while (next_data_line(reader, line)) {
    const std::size_t n = parse_numbers(reader, line, values, expected, max_abs);
    if (cols == 0) {  // first row fixes the width when the caller did not
      cols = n;
      expected = numbers_expected(cols) + " (the width of the first row)";
    }
    if (n != cols) throw InputError(path, reader.line_number(), expected);
    ++rows;
    if (values.size() > limits::kMaxMatrixValues) {
      throw InputError(
          path, reader.line_number(),
          "at most " + std::to_string(limits::kMaxMatrixValues) + " numbers in one matrix file");
    }
  }
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  if (rows > 0) {
    m = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        values.data(), m.rows(), m.cols());
  }
  return m;
}

void write_matrix_text(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m,
                       int significant_digits) {
  check_digits(significant_digits);
  TextFileWriter writer(path);
  // Format into a large chunk and hand it over in one piece: no per-number stream calls.
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  constexpr std::size_t kMaxNumber = 32;  // "-1.2345678901234567e-308" plus a separator
  std::string chunk(kChunk + kMaxNumber + 1, '\0');
  std::size_t used = 0;
  char* const base = chunk.data();
  // A matrix without columns has no rows either once read back, so it is written as empty.
  const Eigen::Index rows = m.cols() > 0 ? m.rows() : 0;
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      if (c > 0) base[used++] = ' ';
      char* const first = base + used;
      used = static_cast<std::size_t>(
          format_number(first, first + kMaxNumber, m(r, c), significant_digits) - base);
      if (used >= kChunk) {
        writer.write(std::string_view(base, used));
        used = 0;
      }
    }
    base[used++] = '\n';
    if (used >= kChunk) {
      writer.write(std::string_view(base, used));
      used = 0;
    }
  }
  writer.write(std::string_view(base, used));
  writer.commit();
}

Eigen::MatrixXd as_written(const Eigen::Ref<const Eigen::MatrixXd>& m, int significant_digits) {
  check_digits(significant_digits);
  Eigen::MatrixXd out(m.rows(), m.cols());
  char text[40];
  for (Eigen::Index c = 0; c < m.cols(); ++c) {
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
      // The reader's parse (from_chars), so that the value is bit for bit the one read back.
      char* const end = format_number(text, text + sizeof text, m(r, c), significant_digits);
      if (!parse_number(std::string_view(text, static_cast<std::size_t>(end - text)), out(r, c)))
        throw std::invalid_argument("as_written: cannot read back a written number");
    }
  }
  return out;
}

}  // namespace loopscan::io
