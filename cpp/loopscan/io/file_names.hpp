#pragma once
// File-name tests shared by the readers that pick a format by extension.
#include <string_view>

namespace loopscan::io {

// C++17's std::string has no ends_with.
inline bool ends_with(std::string_view name, std::string_view tail) {
  return name.size() >= tail.size() && name.substr(name.size() - tail.size()) == tail;
}

}  // namespace loopscan::io
