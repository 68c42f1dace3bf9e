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

}  // namespace loopscan::io
