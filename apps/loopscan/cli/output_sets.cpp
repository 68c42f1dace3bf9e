#include "cli/output_sets.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

namespace loopscan::cli {
namespace {

std::string& stored_command_line() {
  static std::string line;
  return line;
}

std::vector<std::pair<std::string, std::string>>& open_sets() {
  static std::vector<std::pair<std::string, std::string>> sets;  // staging -> target
  return sets;
}

}  // namespace

void set_command_line(int argc, char** argv) {
  std::string line = "loopscan";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  stored_command_line() = line;
}

const std::string& command_line() { return stored_command_line(); }

void register_staging(const std::string& staging, const std::string& target) {
  open_sets().emplace_back(staging, target);
}

void unregister_staging(const std::string& staging) {
  auto& sets = open_sets();
  for (auto it = sets.begin(); it != sets.end(); ++it) {
    if (it->first == staging) {
      sets.erase(it);
      return;
    }
  }
}

void refuse_inputs_inside(const CLI::App& cmd, const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(out, ec);
  if (ec || !fs::is_directory(target)) return;  // a new directory holds nothing yet
  for (const CLI::Option* option : cmd.get_options()) {
    if (option->check_lname("out")) continue;
    for (std::string value : option->results()) {
      const auto colon = value.find(':');  // `--trajectory kitti:FILE`
      if (!fs::exists(value, ec) && colon != std::string::npos) value = value.substr(colon + 1);
      if (value.empty() || !fs::exists(value, ec)) continue;
      const fs::path input = fs::weakly_canonical(value, ec);
      if (ec) continue;
      const auto [t, i] = std::mismatch(target.begin(), target.end(), input.begin(), input.end());
      if (t == target.end()) {
        throw std::invalid_argument(option->get_name() + " " + value + " lies inside the output " +
                                    "directory " + out + ", which this command replaces as a " +
                                    "whole: choose another output directory");
      }
    }
  }
}

bool starts_with_bytes(const std::string& path, const std::string& magic) {
  std::ifstream in(path, std::ios::binary);
  std::string head(magic.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  return in.gcount() == static_cast<std::streamsize>(magic.size()) && head == magic;
}

std::string shown(const std::string& path) {
  for (const auto& [staging, target] : open_sets()) {
    if (path.compare(0, staging.size(), staging) == 0) return target + path.substr(staging.size());
  }
  return path;
}

}  // namespace loopscan::cli
