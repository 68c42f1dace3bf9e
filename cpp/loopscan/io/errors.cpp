#include <loopscan/io/errors.hpp>

namespace loopscan::io {
namespace {

std::string format_message(const std::string& file, std::size_t line,
                           const std::string& what_expected) {
  std::string msg = file;
  if (line > 0) msg += ":" + std::to_string(line);
  msg += ": expected " + what_expected;
  return msg;
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

}  // namespace loopscan::io
