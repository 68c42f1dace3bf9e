#pragma once
// Flag values shared by several subcommands.
#include <string>

#include "loopscan/core/types.hpp"

namespace loopscan::cli {

inline Mode parse_mode(const std::string& name) {
  if (name == "reference") return Mode::Reference;
  if (name == "default") return Mode::Default;
  throw std::invalid_argument("unknown mode '" + name + "' (expected reference or default)");
}

inline std::string mode_name(Mode mode) {
  return mode == Mode::Reference ? "reference" : "default";
}

}  // namespace loopscan::cli
