// The numbers `loopscan demo` prints are recomputed by `describe` + `evaluate` on the files it
// wrote (its report/reproduce.sh), to the printed digits and to the last bit of metrics.json.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/cli_support.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// The demo's table: method -> the six printed numbers (same season, then cross season).
std::map<std::string, std::vector<std::string>> printed_table(const std::string& output) {
  std::map<std::string, std::vector<std::string>> table;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string method, word;
    words >> method;
    if (method != "sc" && method != "m2dp" && method != "delight") continue;
    std::vector<std::string> numbers;
    while (words >> word && numbers.size() < 6)
      if (word != "|") numbers.push_back(word);
    table[method] = numbers;
  }
  return table;
}

std::string four_digits(const nlohmann::json& x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", x.get<double>());
  return buf;
}

TEST(Cli, DemoTableIsRecomputedFromItsFiles) {
  const fs::path d = temp_dir("reproduce");
  // builtin:short keeps it fast: same-season and cross-season loops, the demo's code path.
  const CliResult demo =
      run("demo --trajectory builtin:short --seed 7 --out " + (d / "demo").string());
  ASSERT_EQ(demo.code, 0) << demo.output;
  const fs::path script = d / "demo/report/reproduce.sh";
  ASSERT_TRUE(fs::exists(script));
  EXPECT_NE(demo.output.find("reproduce.sh"), std::string::npos) << demo.output;
  // Steps are numbered once each, in order, and every part ends with its own time.
  std::size_t at = 0;
  for (int k = 1; k <= 8; ++k) {
    const std::string step = "[" + std::to_string(k) + "/8] ";
    const std::size_t found = demo.output.find(step);
    ASSERT_NE(found, std::string::npos) << step << demo.output;
    EXPECT_GE(found, at) << step;
    EXPECT_EQ(demo.output.find(step, found + 1), std::string::npos) << step;
    at = found;
  }
  EXPECT_NE(demo.output.find("  describe winter: "), std::string::npos) << demo.output;
  EXPECT_NE(demo.output.find("  match winter vs summer: "), std::string::npos) << demo.output;
  const auto table = printed_table(demo.output);
  ASSERT_EQ(table.size(), 3u) << demo.output;

  const std::string log = (d / "reproduce.log").string();
  const std::string cmd = "LOOPSCAN=" + std::string(LOOPSCAN_CLI) + " sh " + script.string() + " " +
                          (d / "again").string() + " >" + log + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << file_bytes(log);

  const nlohmann::json written = read_json(d / "demo/report/metrics.json");
  ASSERT_EQ(written.size(), 3u);
  int loops = 0;
  for (const nlohmann::json& m : written) {
    const std::string method = m["method"].get<std::string>();
    const std::vector<std::string>& shown = table.at(method);
    ASSERT_EQ(shown.size(), 6u) << method;
    int k = 0;
    for (const char* season : {"same", "cross"}) {
      const nlohmann::json again =
          read_json(d / "again" / (method + "-" + season) / "metrics.json");
      const nlohmann::json& demo_m = m[std::string(season) + "_season"];
      loops += again["n_gt_loops"].get<int>();
      EXPECT_EQ(again["n_gt_loops"], demo_m["n_gt_loops"]) << method << " " << season;
      for (const char* key : {"auc", "recall_at_100_precision", "f1_max"}) {
        // Every bit, not only the printed digits: rounding moves them only now and then.
        EXPECT_EQ(again[key].get<double>(), demo_m[key].get<double>())
            << method << " " << season << " " << key;
        EXPECT_EQ(four_digits(again[key]), shown[static_cast<std::size_t>(k++)])
            << method << " " << season << " " << key;
      }
    }
  }
  EXPECT_GT(loops, 0);  // something was scored
  fs::remove_all(d);
}

}  // namespace
}  // namespace loopscan
