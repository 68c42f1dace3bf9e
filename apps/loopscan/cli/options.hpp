#pragma once
// Flag values shared by several subcommands.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

namespace loopscan::cli {

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
