#pragma once
// Exception type for malformed or unreadable input files.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace loopscan::io {

// Bad input: the message names the file, the 1-based line (0 = whole file) and what was
// expected there, e.g. "poses.txt:12: expected keyframe ids in increasing order".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, std::size_t line, const std::string& what_expected);
  // Binary files: "file: byte N: problem" (line() is 0, what_expected() the problem).
  struct Byte {
    std::size_t offset;
  };
  InputError(const std::string& file, Byte at, const std::string& problem);

  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  const std::string& what_expected() const { return what_expected_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string what_expected_;
};

// For "did you mean" in messages: the name nearest to `word` by edit distance, or "" when none is
// close (more than a third of the word's letters, at least 2, would have to change).
std::string closest_name(const std::string& word, const std::vector<std::string>& names);

}  // namespace loopscan::io
