#pragma once
// Expecting a clear input error: `read(path)` throws io::InputError naming `path` and saying
// `fragment` (what was expected there).
#include <gtest/gtest.h>

#include <string>

#include "loopscan/io/errors.hpp"

namespace loopscan::test {

template <typename Read>
void expect_input_error(const Read& read, const std::string& path, const std::string& fragment) {
  try {
    read(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace loopscan::test
