// The `loopscan` CLI contract: describe, evaluate and pairs outputs; bad input (exit code 2,
// file:line).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cli/cli_support.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

TEST(Cli, DescribeWritesTheContractFiles) {
  const fs::path d = temp_dir("describe");
  write_sequence(d, 40);
  for (const std::string method : {"sc", "m2dp", "delight"}) {
    const CliResult r =
        run("describe --method " + method + " --poses " + (d / "poses.txt").string() +
            " --points " + (d / "pts.txt").string() + " --out " + (d / method).string());
    ASSERT_EQ(r.code, 0) << r.output;
    std::ifstream ids(d / method / "incoming_id_file.txt");
    int n = 0, id;
    while (ids >> id) ++n;
    EXPECT_EQ(n, 10);  // 40 keyframes - INIT_FRAME
    nlohmann::json timing;
    std::ifstream(d / method / "timing.json") >> timing;
    EXPECT_TRUE(timing.contains("imitate_ms"));
    EXPECT_TRUE(timing.contains("describe_ms"));
    // Lateral versions are Scan Context's alone.
    EXPECT_EQ(timing.contains("lateral_versions_m"), method == "sc") << method;
    std::ifstream sigs(d / method / "signatures.txt");
    std::string line;
    int rows = 0;
    while (std::getline(sigs, line)) ++rows;
    // Scan Context: the place and its 4 default lateral versions.
    EXPECT_EQ(rows, 10 * (method == "sc" ? 5 : method == "m2dp" ? 4 : 16));
  }
  EXPECT_FALSE(has_temp_files(d));
}

TEST(Cli, MalformedLineNamesFileAndLineWithExitCode2) {
  const fs::path d = temp_dir("malformed");
  write_sequence(d, 40);
  write(d / "bad_pts.txt", "0 1 2 3 100\n0 1 2 oops 100\n");
  const CliResult r =
      run("describe --method sc --poses " + (d / "poses.txt").string() + " --points " +
          (d / "bad_pts.txt").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("bad_pts.txt:2"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "out" / "signatures.txt"));
  write(d / "short_poses.txt", "0 1 0 0 0 0 1 0 0 0 0 1\n");  // 12 numbers, not 13
  const CliResult r2 =
      run("describe --method sc --poses " + (d / "short_poses.txt").string() + " --points " +
          (d / "pts.txt").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r2.code, 2);
  EXPECT_NE(r2.output.find("short_poses.txt:1"), std::string::npos) << r2.output;
}

TEST(Cli, MissingFileUnknownMethodAndFormatAreClearErrors) {
  const fs::path d = temp_dir("unknown");
  write_sequence(d, 40);
  const std::string base = " --poses " + (d / "poses.txt").string() + " --points " +
                           (d / "pts.txt").string() + " --out " + (d / "o").string();
  CliResult r = run("describe --method nope" + base);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("unknown method"), std::string::npos) << r.output;
  r = run("describe --method sc --poses /nonexistent/p.txt --points x --out " +
          (d / "o2").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("/nonexistent/p.txt"), std::string::npos) << r.output;
  ASSERT_EQ(run("describe --method sc" + base).code, 0);
  // Ground truth is told apart by its numbers a line (12: KITTI poses, 3: RobotCar GPS).
  write(d / "gt5.txt", "1 2 3 4 5\n");
  r = run("evaluate --signatures " + (d / "o").string() + " --gt " + (d / "gt5.txt").string() +
          " --out " + (d / "e").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("gt5.txt:1: expected 12 numbers a line (KITTI poses) or 3"),
            std::string::npos)
      << r.output;
}

TEST(Cli, NanSkippedAndIntensityClampedWithWarnings) {
  const fs::path d = temp_dir("nan");
  write_sequence(d, 40);
  std::ifstream in(d / "pts.txt");
  std::string all((std::istreambuf_iterator<char>(in)), {});
  write(d / "pts2.txt", all + "39 nan 1 2 100\n39 1 1 2 300\n");
  const CliResult r =
      run("describe --method sc --poses " + (d / "poses.txt").string() + " --points " +
          (d / "pts2.txt").string() + " --out " + (d / "o").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("skipped 1 points"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("clamped 1 intensities"), std::string::npos) << r.output;
}

TEST(Cli, FewerKeyframesThanInitFrameIsAMessageNotACrash) {
  const fs::path d = temp_dir("few");
  write_sequence(d, 12);
  const CliResult r = run("describe --method delight --poses " + (d / "poses.txt").string() +
                          " --points " + (d / "pts.txt").string() + " --out " + (d / "o").string());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("no signatures"), std::string::npos) << r.output;
}

TEST(Cli, EvaluateOnFixtureWritesMetricsCsvAndSvg) {
  LOOPSCAN_REQUIRE_FIXTURE();
  const fs::path d = temp_dir("evaluate");
  const std::string f = test::fixture_dir();
  const CliResult r = run(
      "evaluate --method sc --signatures " + f + "/reference/signatures_sc.txt.gz" + " --ids " + f +
      "/reference/incoming_id_file.txt --gt " + f + "/gt.txt --mode reference --out " + d.string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json m;
  std::ifstream(d / "metrics.json") >> m;
  for (const char* key :
       {"auc", "recall_at_100_precision", "f1_max", "n_queries", "n_gt_loops", "query_ms"}) {
    EXPECT_TRUE(m.contains(key)) << key;
  }
  nlohmann::json ref;
  std::ifstream(f + "/reference/metrics.json") >> ref;
  EXPECT_NEAR(m["auc"].get<double>(), ref["sc"]["fused"]["auc"].get<double>(), 1e-4);
  std::ifstream svg(d / "pr.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), {});
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("AUC"), std::string::npos);
  std::ifstream matches(d / "matches.csv");
  std::string header;
  std::getline(matches, header);
  EXPECT_EQ(header, "query_id,matched_id,distance,is_true");
  EXPECT_FALSE(has_temp_files(d));
}

TEST(Cli, PairsReproducesThePeerF1Max) {
  const std::string dir = test::shared_dir() + "/data/peers/lidar-iris-kitti";
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(dir + "/06_score_label.txt.gz"), dir);
  const fs::path d = temp_dir("pairs");
  const CliResult r = run("pairs --scores " + dir + "/06_score_label.txt.gz --out " + d.string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json m;
  std::ifstream(d / "metrics.json") >> m;
  double reported;
  std::ifstream(dir + "/06_f1max.txt") >> reported;
  EXPECT_NEAR(m["f1_max"].get<double>(), reported, 1e-9);
}

}  // namespace
}  // namespace loopscan
