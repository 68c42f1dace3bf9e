#pragma once
// A scratch directory per test with helpers to write text / gzip files and to expect the
// InputError a reader throws ("<path>:<line>: expected ...").
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include <loopscan/io/errors.hpp>

namespace loopscan::test {

namespace fs = std::filesystem;
using io::InputError;

inline bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Runs `f` and returns the message of the E it throws (a test failure when it throws none).
template <typename E = InputError>
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "no exception";
  return "";
}

// Expects `f` to throw InputError "<path>:<line>: expected ...<part>..." (no line when 0).
inline void expect_input_error(const std::function<void()>& f, const std::string& path,
                               std::size_t line, const std::string& part) {
  const std::string msg = error_of(f);
  const std::string where = line > 0 ? path + ":" + std::to_string(line) + ":" : path + ":";
  EXPECT_EQ(msg.rfind(where + " expected ", 0), 0u) << msg;
  EXPECT_TRUE(has(msg, part)) << msg;
}

class IoFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("loopscan_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string file(const std::string& name, const std::string& content) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  std::string gz_file(const std::string& name, const std::string& content) const {
    const std::string p = (dir_ / name).string();
    gzFile f = gzopen(p.c_str(), "wb");
    EXPECT_EQ(gzwrite(f, content.data(), static_cast<unsigned>(content.size())),
              static_cast<int>(content.size()));  // also fails when gzopen did
    gzclose(f);
    return p;
  }
  static std::string slurp(const std::string& p) {
    return {std::istreambuf_iterator<char>(std::ifstream(p, std::ios::binary).rdbuf()), {}};
  }
  // Writes `content` to a fresh file and expects `read(path)` to throw InputError at `line`.
  template <typename Read>
  void expect_bad(Read read, const std::string& content, std::size_t line,
                  const std::string& part) {
    const std::string p = file("bad" + std::to_string(++n_bad_) + ".txt", content);
    expect_input_error([&] { read(p); }, p, line, part);
  }
  fs::path dir_;
  int n_bad_ = 0;
};

}  // namespace loopscan::test
