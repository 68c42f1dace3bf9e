#include <loopscan/io/parse_numbers.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>
#include <type_traits>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/limits.hpp>
#include <loopscan/io/line_reader.hpp>

namespace loopscan::io {
namespace {

template <typename T>
bool parse_token(std::string_view token, T& out) {
  // from_chars rejects the '+' sign that iostream and strtod accept.
  if (token.size() > 1 && token[0] == '+' && token[1] != '+' && token[1] != '-') {
    token.remove_prefix(1);
  }
  const char* first = token.data();
  const char* last = first + token.size();
  const auto [ptr, ec] = std::from_chars(first, last, out);
  if (ptr != last || token.empty()) return false;
  if (ec == std::errc()) return true;
  if constexpr (std::is_floating_point_v<T>) {
    // Rare path: from_chars leaves `out` untouched on overflow/underflow; strtod saturates.
    if (ec == std::errc::result_out_of_range) {
      const std::string copy(token);
      if constexpr (std::is_same_v<T, float>) {
        out = std::strtof(copy.c_str(), nullptr);
      } else {
        out = std::strtod(copy.c_str(), nullptr);
      }
      return true;
    }
  }
  return false;
}

[[noreturn]] void fail(const LineReader& reader, std::string_view expected) {
  throw InputError(reader.path(), reader.line_number(), std::string(expected));
}

[[noreturn]] void fail_bound(const LineReader& reader, std::string_view expected, double max_abs) {
  throw InputError(reader.path(), reader.line_number(),
                   std::string(expected) + ", each finite and within " + bound_text(max_abs));
}

}  // namespace

bool is_blank(std::string_view line) {
  for (char c : line) {
    if (!is_blank_char(c)) return false;
  }
  return true;
}

bool Tokenizer::next(std::string_view& token) {
  std::size_t i = 0;
  while (i < rest_.size() && is_blank_char(rest_[i])) ++i;
  if (i == rest_.size()) {
    rest_ = {};
    return false;
  }
  std::size_t j = i;
  while (j < rest_.size() && !is_blank_char(rest_[j])) ++j;
  token = rest_.substr(i, j - i);
  rest_.remove_prefix(j);
  return true;
}

bool Tokenizer::at_end() const {
  std::string_view token;
  Tokenizer copy = *this;
  return !copy.next(token);
}

bool parse_number(std::string_view token, double& out) { return parse_token(token, out); }
bool parse_number(std::string_view token, float& out) { return parse_token(token, out); }
bool parse_number(std::string_view token, int& out) { return parse_token(token, out); }

void check_record_count(const LineReader& reader, std::size_t count, const char* what) {
  if (count > limits::kMaxRecords) {
    throw InputError(
        reader.path(), reader.line_number(),
        "at most " + std::to_string(limits::kMaxRecords) + " " + what + " in one file");
  }
}

std::string bound_text(double max_abs) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "+-%g", max_abs);
  return buf;
}

std::size_t parse_numbers(const LineReader& reader, std::string_view line, std::vector<double>& out,
                          std::string_view expected, double max_abs) {
  Tokenizer tokens(line);
  std::string_view token;
  std::size_t count = 0;
  double value = 0.0;
  while (tokens.next(token)) {
    if (!parse_number(token, value)) fail(reader, expected);
    if (!(std::abs(value) <= max_abs)) fail_bound(reader, expected, max_abs);
    out.push_back(value);
    ++count;
  }
  return count;
}

void parse_exactly(const LineReader& reader, Tokenizer& tokens, double* out, std::size_t n,
                   std::string_view expected, double max_abs) {
  std::string_view token;
  for (std::size_t i = 0; i < n; ++i) {
    if (!tokens.next(token) || !parse_number(token, out[i])) fail(reader, expected);
    if (!(std::abs(out[i]) <= max_abs)) fail_bound(reader, expected, max_abs);
  }
  if (!tokens.at_end()) fail(reader, expected);
}

}  // namespace loopscan::io
