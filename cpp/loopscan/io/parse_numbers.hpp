#pragma once
// Number parsing shared by every reader: std::from_chars on blank-separated tokens.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace loopscan::io {

class LineReader;

// Space, tab, CR, vertical tab and form feed separate tokens.
inline bool is_blank_char(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool is_blank(std::string_view line);

// Splits a line into blank-separated tokens without copying.
class Tokenizer {
 public:
  explicit Tokenizer(std::string_view line) : rest_(line) {}
  // Next token; false when the line is exhausted.
  bool next(std::string_view& token);
  // True when only blanks remain.
  bool at_end() const;

 private:
  std::string_view rest_;
};

// Whole-token parses; false on junk, trailing characters or (for int) out-of-range values.
// Floating tokens accept a leading '+', "nan" and "inf"; values beyond the type's range become
// +-inf (or underflow to 0 / denormals) as with strtod, instead of being rejected.
bool parse_number(std::string_view token, double& out);
bool parse_number(std::string_view token, float& out);
bool parse_number(std::string_view token, int& out);

// Appends every number of `line` to `out` and returns how many were appended. A token that is
// not a finite number of magnitude <= max_abs throws InputError(reader.path(),
// reader.line_number(), expected + the bound).
std::size_t parse_numbers(const LineReader& reader, std::string_view line, std::vector<double>& out,
                          std::string_view expected, double max_abs);

// Parses exactly `n` doubles from the remaining tokens into out[0..n). Fewer, more or junk
// tokens, NaN, infinity and magnitudes above max_abs throw InputError(reader.path(),
// reader.line_number(), expected + the bound).
void parse_exactly(const LineReader& reader, Tokenizer& tokens, double* out, std::size_t n,
                   std::string_view expected, double max_abs);

// Throws InputError(reader.path(), reader.line_number(), "at most N <what> in one file") once
// `count` passes io::limits::kMaxRecords.
void check_record_count(const LineReader& reader, std::size_t count, const char* what);

// "+-1e+09" for the messages.
std::string bound_text(double max_abs);

}  // namespace loopscan::io
