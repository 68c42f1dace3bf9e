#pragma once
// Flag values shared by several subcommands.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

#include "cli/guidance.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/core/signature.hpp"
#include "loopscan/core/types.hpp"

namespace loopscan::cli {

// --method of the commands that also take the image baselines (for a name that is not gist or
// bow): the LiDAR-style method, or an error listing all five and the closest one.
inline Method parse_method_or_image(const std::string& name) {
  try {
    return parse_method(name);
  } catch (const std::invalid_argument&) {
    std::string message = "unknown method '" + name + "' (expected sc, m2dp, delight, gist or bow";
    const std::string guess = io::closest_name(name, {"sc", "m2dp", "delight", "gist", "bow"});
    if (!guess.empty()) message += "; did you mean '" + guess + "'?";
    throw std::invalid_argument(message + ")");
  }
}

// Option check: a finite number in [lo, hi] (CLI11's own Range lets NaN and "inf" through).
// A failure is a CLI::ValidationError: exit code 2, the option and the range named.
inline CLI::Validator finite_in(double lo, double hi) {
  char range[64];
  std::snprintf(range, sizeof range, "a finite number in [%g, %g]", lo, hi);
  const std::string expected = range;
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        errno = 0;
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < lo ||
            v > hi) {
          return "expected " + expected + ", got '" + text + "'";
        }
        return "";
      },
      expected);
}

// The bounds shared by several commands.
constexpr double kMaxThreads = 256;
constexpr double kMaxCount = 1e9;  // ids, frame counts, masks

}  // namespace loopscan::cli
