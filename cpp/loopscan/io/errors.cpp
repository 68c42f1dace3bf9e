#include <loopscan/io/errors.hpp>

#include <algorithm>

namespace loopscan::io {
namespace {

std::string format_message(const std::string& file, std::size_t line,
                           const std::string& what_expected) {
  std::string msg = file;
  if (line > 0) msg += ":" + std::to_string(line);
  msg += ": expected " + what_expected;
  return msg;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

InputError::InputError(const std::string& file, std::size_t line, const std::string& what_expected)
    : std::runtime_error(format_message(file, line, what_expected)),
      file_(file),
      line_(line),
      what_expected_(what_expected) {}

InputError::InputError(const std::string& file, Byte at, const std::string& problem)
    : std::runtime_error(file + ": byte " + std::to_string(at.offset) + ": " + problem),
      file_(file),
      line_(0),
      what_expected_(problem) {}

std::string closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance || (c.rfind(word, 0) == 0 && word.size() >= 3 && best.empty())) {
      best_distance = std::min(d, best_distance);
      best = c;
    }
  }
  return best;
}

}  // namespace loopscan::io
