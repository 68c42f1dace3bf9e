// The configuration from the command line: `loopscan config`, `--config` on every command with
// tuning, the configuration written next to every result, the mode travelling with the
// signatures, and short option lists.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli/cli_support.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

nlohmann::json json_of(const fs::path& p) {
  nlohmann::json j;
  std::ifstream(p) >> j;
  return j;
}

// Ground truth of write_sequence's keyframes: camera-to-world, the camera at z = -id... as the
// VO poses say (world-to-camera translation -id along z).
void write_gt(const fs::path& p, int frames) {
  std::ostringstream gt;
  for (int id = 0; id < frames; ++id) gt << "1 0 0 0 0 1 0 0 0 0 1 " << id << "\n";
  write(p, gt.str());
}

std::string describe(const fs::path& d, const std::string& method, const std::string& extra,
                     const fs::path& out) {
  return "describe --method " + method + " --poses " + (d / "poses.txt").string() + " --points " +
         (d / "pts.txt").string() + extra + " --out " + out.string();
}

TEST(CliConfig, ConfigPrintsEveryDefaultAndReadsAnEditedFileBack) {
  const fs::path d = temp_dir("config_" + std::to_string(getpid()));
  CliResult r = run("config");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* line : {"method: sc", "mode: default", "  range_m: 45", "    frame: camera",
                           "    lateral_versions_m: [-3.5, -1.75, 1.75, 3.5]", "  fusion: adaptive",
                           "    min_overlap: 0.45", "    odometry_translation_per_m: 0.03",
                           "  points_per_keyframe: 1000", "    drift_translation_per_m: 0.004"}) {
    EXPECT_NE(r.output.find(std::string("\n") + line), std::string::npos) << line;
  }
  r = run("config --method m2dp --mode reference");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("\nmethod: m2dp"), std::string::npos);
  EXPECT_NE(r.output.find("\n  fusion: fused"), std::string::npos);  // the paper's
  EXPECT_NE(r.output.find("    lateral_versions_m: []"), std::string::npos);
  // Dump, edit, load: the edited value, and every other key as it was.
  ASSERT_EQ(run("config --out " + (d / "c.yaml").string()).code, 0);
  std::string text = file_bytes(d / "c.yaml");
  const std::string before = "    min_overlap: 0.45", after = "    min_overlap: 0.3";
  ASSERT_NE(text.find(before), std::string::npos);
  text.replace(text.find(before), before.size(), after);
  write(d / "edited.yaml", text);
  r = run("config --config " + (d / "edited.yaml").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(after + "\n"), std::string::npos) << r.output;
  const std::string dump = file_bytes(d / "c.yaml");
  EXPECT_EQ(r.output.substr(r.output.find("\nmethod:")), [&] {
    std::string t = dump.substr(dump.find("\nmethod:"));
    t.replace(t.find(before), before.size(), after);
    return t;
  }());
  // `config --out` replaces a configuration it wrote, never another file.
  ASSERT_EQ(run("config --mode reference --out " + (d / "c.yaml").string()).code, 0);
  EXPECT_NE(file_bytes(d / "c.yaml").find("\nmode: reference"), std::string::npos);
  write(d / "notes.yaml", "my notes\n");
  r = run("config --out " + (d / "notes.yaml").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(file_bytes(d / "notes.yaml"), "my notes\n");
}

TEST(CliConfig, BadFilesAreRefusedNamingFileLineAndKey) {
  const fs::path d = temp_dir("config_bad_" + std::to_string(getpid()));
  write_sequence(d, 40);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"imitation:\n  rang_m: 30\n", ":2: expected a key of 'imitation'"},
      {"imitation:\n  range_m: far\n",
       ":2: expected a number in [0.1, 1000] for imitation.range_m"},
      {"imitation:\n  range_m: 5000\n", ":2: expected a number in [0.1, 1000]"},
      {"descriptors:\n  scan_context:\n    frame: sideways\n", ":3: expected pca, camera"},
      {"mode: reference\ndescriptors:\n  scan_context:\n    frame: camera\n",
       "reference mode is the paper's PCA frame"},
      {"closure: 3\n", ":1: expected a map of keys for closure"},
      {"method: sc\nmethod: m2dp\n", ":2: expected each key once"},
  };
  for (const auto& [yaml, expected] : cases) {
    const std::string config = test::config(d, "bad", yaml);
    const CliResult r = run(describe(d, "sc", config, d / "o"));
    EXPECT_EQ(r.code, 2) << yaml << r.output;
    EXPECT_NE(r.output.find((d / "bad.yaml").string()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << yaml << "\n" << r.output;
    EXPECT_FALSE(fs::exists(d / "o"));
  }
  // Loop closing takes forward-only scans: a two-sided file is refused before any work.
  const CliResult closing =
      run("close --poses " + (d / "poses.txt").string() + " --points " + (d / "pts.txt").string() +
          config(d, "two_sided", "imitation:\n  lookahead_m: 20\n") + " --out " +
          (d / "c").string());
  EXPECT_EQ(closing.code, 2);
  EXPECT_NE(closing.output.find("two_sided.yaml:2: expected a configuration for loop closing: "
                                "imitation.lookahead_m"),
            std::string::npos)
      << closing.output;
  EXPECT_FALSE(fs::exists(d / "c"));
  // The file's method or mode against a flag: both named.
  const CliResult r = run(describe(d, "m2dp", config(d, "m", "method: sc\n"), d / "o"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("conflicting methods: --method says m2dp, " + (d / "m.yaml").string() +
                          ":1 says sc"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(run("describe --method sc --config " + (d / "none.yaml").string() +
                " --poses x "
                "--points y --out " +
                (d / "o").string())
                .code,
            2);
}

// What a file sets reaches the stage, and the configuration used is written beside the results.
TEST(CliConfig, ConfigReachesTheStagesAndIsWrittenBesideEveryResult) {
  const fs::path d = temp_dir("config_use_" + std::to_string(getpid()));
  write_sequence(d, 40);
  write_gt(d / "gt.txt", 40);
  ASSERT_EQ(run(describe(d, "sc", "", d / "sc45")).code, 0);
  const std::string range30 = config(d, "r30", "imitation:\n  range_m: 30\n");
  ASSERT_EQ(run(describe(d, "sc", range30, d / "sc30")).code, 0);
  EXPECT_EQ(json_of(d / "sc30/timing.json")["range_m"].get<double>(), 30.0);
  EXPECT_NE(file_bytes(d / "sc30/signatures.txt"), file_bytes(d / "sc45/signatures.txt"));
  EXPECT_NE(file_bytes(d / "sc30/config.yaml").find("\n  range_m: 30  #"), std::string::npos);
  // A set's config.yaml goes back into --config as it is.
  const std::string again = " --config " + (d / "sc30/config.yaml").string();
  ASSERT_EQ(run(describe(d, "sc", again, d / "sc30b")).code, 0);
  EXPECT_EQ(file_bytes(d / "sc30b/signatures.txt"), file_bytes(d / "sc30/signatures.txt"));
  // One descriptor per place instead of the lateral versions: 1 row a place, not 5.
  ASSERT_EQ(
      run(describe(d, "sc",
                   config(d, "v0", "descriptors:\n  scan_context:\n    lateral_versions_m: []\n"),
                   d / "v0"))
          .code,
      0);
  EXPECT_EQ(read_lines(d / "v0/signatures.txt").size(), 10u);
  EXPECT_EQ(read_lines(d / "sc45/signatures.txt").size(), 50u);
  // evaluate: the protocol from the file, the configuration beside the metrics.
  const std::string protocol =
      config(d, "p", "evaluation:\n  same_session:\n    threshold_m: 3\n    mask: 2\n");
  CliResult r = run("evaluate --signatures " + (d / "sc45").string() + " --gt " +
                    (d / "gt.txt").string() + protocol + " --out " + (d / "e").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = json_of(d / "e/metrics.json");
  EXPECT_EQ(m["protocol"]["threshold_m"].get<double>(), 3.0);
  EXPECT_EQ(m["protocol"]["mask_width"].get<int>(), 2);
  EXPECT_EQ(m["method"], "sc");
  EXPECT_NE(file_bytes(d / "e/config.yaml").find("    threshold_m: 3  #"), std::string::npos);
  // Every written config.yaml loads back.
  for (const char* dir : {"sc45", "sc30", "v0", "e"}) {
    r = run("config --config " + (d / dir / "config.yaml").string());
    EXPECT_EQ(r.code, 0) << dir << r.output;
  }
}

// The bird's-eye place's layout and search from the file: describe writes places of that layout,
// and evaluate and db match them in it without being told; sets of two layouts do not compare.
TEST(CliConfig, BirdsEyeLayoutTravelsWithTheSignatures) {
  const fs::path d = temp_dir("config_bev_" + std::to_string(getpid()));
  write_sequence(d, 40);
  write_gt(d / "gt.txt", 40);
  const std::string small = config(d, "small",
                                   "descriptors:\n  birds_eye:\n    cell: height\n    cell_m: 1.5\n"
                                   "    range_m: 24\n    rings: 16\n    angles: 40\n"
                                   "    search:\n      finalists: 2\n");
  CliResult r = run(describe(d, "bev", small, d / "small"));
  ASSERT_EQ(r.code, 0) << r.output;
  r = run(describe(d, "bev", "", d / "default"));
  ASSERT_EQ(r.code, 0) << r.output;
  // Another weight window alone is another layout too.
  const std::string flat = config(d, "flat", "descriptors:\n  birds_eye:\n    taper_start_m: 28\n");
  r = run(describe(d, "bev", flat, d / "flat"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(file_bytes(d / "flat/config.yaml").find("    taper_start_m: 28"), std::string::npos);
  // 32 x 32 cells + 16 x 40 key values a place, against 60 x 60 + 24 x 60.
  const std::string first = read_lines(d / "small/signatures.txt").front();
  EXPECT_EQ(std::count(first.begin(), first.end(), ' ') + 1, 32 * 32 + 16 * 40);
  EXPECT_NE(file_bytes(d / "small/config.yaml").find("    cell: height"), std::string::npos);
  // Evaluated in its own layout without --config; the finalists are a search setting, the
  // default 10 without the file and its 2 with it.
  const std::string gt = " --gt " + (d / "gt.txt").string();
  r = run("evaluate --signatures " + (d / "small").string() + gt + " --out " + (d / "e").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("evaluate --signatures " + (d / "small").string() + gt + small + " --out " +
          (d / "e2").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(file_bytes(d / "e/config.yaml").find("    range_m: 24"), std::string::npos);
  EXPECT_NE(file_bytes(d / "e/config.yaml").find("      finalists: 5"), std::string::npos);
  EXPECT_NE(file_bytes(d / "e2/config.yaml").find("      finalists: 2"), std::string::npos);
  // A map in its layout, queried with the same places.
  r = run("db build --signatures " + (d / "small").string() + gt + " --out " +
          (d / "m.db").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("db query --db " + (d / "m.db").string() + " --signatures " + (d / "small").string() +
          " --exact --k 1 --out " + (d / "q").string());
  ASSERT_EQ(r.code, 0) << r.output;
  // Places of two layouts do not compare: refused naming both.
  r = run("evaluate --signatures " + (d / "small").string() + gt + " --against " +
          (d / "default").string() + " --gt2 " + (d / "gt.txt").string() + " --out " +
          (d / "bad").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("differ in cell_m, range_m, taper_start_m, taper_end_m, rings or angles"),
            std::string::npos)
      << r.output;
  r = run("evaluate --signatures " + (d / "flat").string() + gt + " --against " +
          (d / "default").string() + " --gt2 " + (d / "gt.txt").string() + " --out " +
          (d / "bad2").string());
  EXPECT_EQ(r.code, 2) << r.output;
  // A map of one window refuses queries described with another.
  r = run("db build --signatures " + (d / "flat").string() + gt + " --out " +
          (d / "flat.db").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("db query --db " + (d / "flat.db").string() + " --signatures " +
          (d / "default").string() + " --exact --k 1 --out " + (d / "q2").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("taper_start_m"), std::string::npos) << r.output;
  fs::remove_all(d);
}

// Reference signatures are evaluated as the paper evaluated them without being told; a flag
// that contradicts the signatures is refused; maps keep how their places were described.
TEST(CliConfig, TheModeTravelsWithTheSignatures) {
  const fs::path d = temp_dir("config_mode_" + std::to_string(getpid()));
  write_sequence(d, 60);
  write_gt(d / "gt.txt", 60);
  ASSERT_EQ(run(describe(d, "m2dp", " --mode reference", d / "ref")).code, 0);
  ASSERT_EQ(run(describe(d, "m2dp", "", d / "def")).code, 0);
  const std::string gt = " --gt " + (d / "gt.txt").string();
  CliResult r = run("evaluate --signatures " + (d / "ref").string() + gt + " --out " +
                    (d / "e_ref").string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json m = json_of(d / "e_ref/metrics.json");
  EXPECT_EQ(m["mode"], "reference");
  EXPECT_EQ(m["fusion"], "fused");
  EXPECT_EQ(m["method"], "m2dp");
  r = run("evaluate --signatures " + (d / "def").string() + gt + " --out " +
          (d / "e_def").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(json_of(d / "e_def/metrics.json")["fusion"], "adaptive");
  // Contradictions name both values.
  r = run("evaluate --mode default --signatures " + (d / "ref").string() + gt + " --out " +
          (d / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("conflicting modes: --mode says default, " +
                          (d / "ref/config.yaml").string() + " says reference"),
            std::string::npos)
      << r.output;
  r = run("evaluate --method sc --signatures " + (d / "ref").string() + gt + " --out " +
          (d / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--method says sc"), std::string::npos) << r.output;
  r = run("evaluate --signatures " + (d / "def").string() + gt + " --against " +
          (d / "ref").string() + " --gt2 " + (d / "gt.txt").string() + " --out " +
          (d / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("conflicting modes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "x"));
  // A signature file says nothing: --method is needed.
  r = run("evaluate --signatures " + (d / "ref/signatures.txt").string() + " --ids " +
          (d / "ref/incoming_id_file.txt").string() + gt + " --out " + (d / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--method: no input says which method described it"),
            std::string::npos)
      << r.output;
  // Sets written before config.yaml existed: timing.json says it.
  fs::remove(d / "ref/config.yaml");
  r = run("evaluate --signatures " + (d / "ref").string() + gt + " --out " +
          (d / "e_old").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(json_of(d / "e_old/metrics.json")["fusion"], "fused");
  EXPECT_EQ(json_of(d / "e_old/metrics.json")["auc"], json_of(d / "e_ref/metrics.json")["auc"]);

  // A map records the mode and frame of its places; queries described otherwise are refused.
  ASSERT_EQ(run(describe(d, "sc", "", d / "sc_def")).code, 0);
  ASSERT_EQ(run(describe(d, "sc", " --mode reference", d / "sc_ref")).code, 0);
  ASSERT_EQ(
      run("db build --signatures " + (d / "sc_ref").string() + " --out " + (d / "ref.db").string())
          .code,
      0);
  r = run("db query --db " + (d / "ref.db").string() + " --signatures " + (d / "sc_def").string() +
          " --out " + (d / "q").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("ref.db says reference"), std::string::npos) << r.output;
  r = run("db query --db " + (d / "ref.db").string() + " --signatures " + (d / "sc_ref").string() +
          " --out " + (d / "q").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(file_bytes(d / "q/config.yaml").find("\nmode: reference"), std::string::npos);
  r = run("db build --signatures " + (d / "sc_ref").string() + " --signatures " +
          (d / "sc_def").string() + " --out " + (d / "mixed.db").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("conflicting modes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "mixed.db"));
  // The frame travels too: a camera-frame map refuses PCA-frame queries.
  const std::string pca = config(
      d, "pca", "descriptors:\n  scan_context:\n    frame: pca\n    lateral_versions_m: []\n");
  ASSERT_EQ(run(describe(d, "sc", pca, d / "sc_pca")).code, 0);
  ASSERT_EQ(
      run("db build --signatures " + (d / "sc_def").string() + " --out " + (d / "def.db").string())
          .code,
      0);
  r = run("db query --db " + (d / "def.db").string() + " --signatures " + (d / "sc_pca").string() +
          " --out " + (d / "q2").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("conflicting descriptor frames"), std::string::npos) << r.output;
}

// The authors' numbers from reference signatures without --mode (held-out: KITTI 05; here the
// k06 fixture, whose authors' metrics are shared).
TEST(CliConfig, ReferenceSignaturesEvaluatedWithoutModeGiveTheAuthorsMetrics) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const fs::path d = temp_dir("config_k06_" + std::to_string(getpid()));
  const std::string f = test::fixture_dir();
  CliResult r = run("describe --method sc --mode reference --poses " + f +
                    "/poses_history_file.txt --points " + f + "/pts_history_file.txt.gz --out " +
                    (d / "sc").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("evaluate --signatures " + (d / "sc").string() + " --gt " + f + "/gt.txt --out " +
          (d / "e").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = json_of(d / "e/metrics.json");
  const nlohmann::json ref = json_of(f + "/reference/metrics.json");
  EXPECT_NEAR(m["auc"].get<double>(), ref["sc"]["fused"]["auc"].get<double>(), 1e-4);
  EXPECT_NEAR(m["recall_at_100_precision"].get<double>(),
              ref["sc"]["fused"]["recall_at_100_precision"].get<double>(), 1e-4);
}

// A line of CLI11's help that lists an option: indented, `--name` or `-x,--name` first.
bool lists_an_option(const std::string& line) {
  const std::size_t start = line.find_first_not_of(' ');
  if (start == 0 || start == std::string::npos) return false;
  std::string rest = line.substr(start);
  if (rest.size() > 3 && rest[0] == '-' && rest[1] != '-' && rest[2] == ',') rest = rest.substr(3);
  return rest.size() > 2 && rest.rfind("--", 0) == 0 && std::islower(rest[2]);
}

// Every command shows at most 12 options besides --help.
TEST(CliConfig, EveryCommandHasAtMostTwelveOptions) {
  for (const char* command :
       {"describe", "evaluate", "pairs", "plot", "simulate", "demo", "render", "vo", "run", "slam",
        "close", "config", "db build", "db query", "vocab train"}) {
    const CliResult r = run(std::string(command) + " --help");
    ASSERT_EQ(r.code, 0) << command << r.output;
    int options = 0;
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);) {
      if (lists_an_option(line) && line.find("--help") == std::string::npos) ++options;
    }
    EXPECT_GE(options, 2) << command << "\n" << r.output;
    EXPECT_LE(options, 12) << command << "\n" << r.output;
  }
}

}  // namespace
}  // namespace loopscan
