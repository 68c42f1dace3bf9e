#pragma once
// Running the `loopscan` executable from the CLI tests: exit code and output, scratch
// directories, a small SO-DSO export, file helpers.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace loopscan::test {
namespace fs = std::filesystem;

struct CliResult {
  int code;
  std::string output;
};

inline CliResult run(const std::string& args) {
  const std::string cmd = std::string(LOOPSCAN_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), out};
}

inline fs::path temp_dir(const std::string& name) {
  const fs::path d = temp_path("cli_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

inline void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A small valid SO-DSO export: 40 keyframes driving forward, 30 points each.
inline void write_sequence(const fs::path& dir, int keyframes) {
  std::ostringstream poses, pts;
  for (int id = 0; id < keyframes; ++id) {
    poses << id << " 1 0 0 0 0 1 0 0 0 0 1 " << -1.0 * id << "\n";
    for (int k = 0; k < 30; ++k) {
      pts << id << ' ' << (k % 2 ? -6 : 7) << ' ' << -0.3 * (k % 7) << ' ' << id + 5 + 0.5 * k
          << ' ' << 20 + 7 * k << "\n";
    }
  }
  write(dir / "poses.txt", poses.str());
  write(dir / "pts.txt", pts.str());
}

// " --config FILE" with FILE = dir/name.yaml holding `yaml` (a partial configuration).
inline std::string config(const fs::path& dir, const std::string& name, const std::string& yaml) {
  const fs::path p = dir / (name + ".yaml");
  write(p, yaml);
  return " --config " + p.string();
}

inline std::vector<std::string> read_lines(const fs::path& p) {
  std::vector<std::string> lines;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline bool has_temp_files(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
  }
  return false;
}

inline std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

}  // namespace loopscan::test
