// The `loopscan` executable: the CLI contract, bad input (exit code 2, file:line), atomic
// outputs.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/io/png.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {
namespace fs = std::filesystem;

struct CliResult {
  int code;
  std::string output;
};

CliResult run(const std::string& args) {
  const std::string cmd = std::string(LOOPSCAN_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), out};
}

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("loopscan_cli_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// A small valid SO-DSO export: 40 keyframes driving forward, 30 points each.
void write_sequence(const fs::path& dir, int keyframes) {
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

std::vector<std::string> read_lines(const fs::path& p) {
  std::vector<std::string> lines;
  std::ifstream in(p);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

bool has_temp_files(const fs::path& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
  }
  return false;
}

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
    std::ifstream sigs(d / method / "signatures.txt");
    std::string line;
    int rows = 0;
    while (std::getline(sigs, line)) ++rows;
    EXPECT_EQ(rows, 10 * (method == "sc" ? 1 : method == "m2dp" ? 4 : 16));
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
  r = run("describe --method sc --poses /nonexistent/p.txt --points x --out " + (d / "o2").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("/nonexistent/p.txt"), std::string::npos) << r.output;
  ASSERT_EQ(run("describe --method sc" + base).code, 0);
  r = run("evaluate --method sc --signatures " + (d / "o").string() + " --gt " +
          (d / "poses.txt").string() + " --gt-format euroc --out " + (d / "e").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("euroc"), std::string::npos) << r.output;
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
  const CliResult r =
      run("evaluate --method sc --signatures " + f + "/reference/signatures_sc.txt.gz" + " --ids " +
          f + "/reference/incoming_id_file.txt --gt " + f +
          "/gt.txt --gt-format kitti --mode reference --out " + d.string());
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
  if (!fs::exists(dir + "/06_score_label.txt.gz")) GTEST_SKIP() << "no peer data in " << dir;
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

namespace loopscan {
namespace {

TEST(Cli, SimulateWritesVoExportThatDescribeReads) {
  const fs::path d = temp_dir("simulate");
  const CliResult r = run("simulate --trajectory builtin:short --season winter --seed 3 --out " +
                          (d / "sim").string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"poses_history_file.txt", "pts_history_file.txt", "gt.txt", "world.json"}) {
    EXPECT_TRUE(fs::exists(d / "sim" / f)) << f;
  }
  nlohmann::json world;
  std::ifstream(d / "sim" / "world.json") >> world;
  EXPECT_EQ(world["conditions"]["season"], "winter");
  EXPECT_TRUE(world.contains("world"));
  const CliResult r2 = run(
      "describe --method sc --poses " + (d / "sim/poses_history_file.txt").string() + " --points " +
      (d / "sim/pts_history_file.txt").string() + " --out " + (d / "sc").string());
  ASSERT_EQ(r2.code, 0) << r2.output;
  const CliResult r3 = run("evaluate --method sc --signatures " + (d / "sc").string() + " --gt " +
                           (d / "sim/gt.txt").string() + " --out " + (d / "eval").string());
  ASSERT_EQ(r3.code, 0) << r3.output;
  EXPECT_FALSE(has_temp_files(d));
}

TEST(Cli, SimulateRejectsUnknownTrajectoryAndSeason) {
  const fs::path d = temp_dir("simulate_bad");
  CliResult r = run("simulate --trajectory builtin:moon --out " + d.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("moon"), std::string::npos) << r.output;
  r = run("simulate --trajectory builtin:short --season monsoon --out " + d.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("monsoon"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace loopscan

namespace loopscan {
namespace {

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

TEST(Cli, SimulateIsByteIdenticalForTheSameSeed) {
  const fs::path d = temp_dir("simulate_twice");
  for (const char* name : {"a", "b", "c"}) {
    const std::string seed = std::string(name) == "c" ? "5" : "4";
    ASSERT_EQ(run("simulate --trajectory builtin:short --season fall --seed " + seed + " --out " +
                  (d / name).string())
                  .code,
              0);
  }
  for (const char* f : {"poses_history_file.txt", "pts_history_file.txt", "gt.txt", "world.json"}) {
    EXPECT_EQ(file_bytes(d / "a" / f), file_bytes(d / "b" / f)) << f;
  }
  EXPECT_NE(file_bytes(d / "a" / "pts_history_file.txt"),
            file_bytes(d / "c" / "pts_history_file.txt"));
}

TEST(Cli, DbBuildAndQueryReproduceTheCrossSessionEvaluation) {
  const fs::path d = temp_dir("db");
  for (const char* season : {"summer", "fall"}) {
    const std::string sim = (d / season).string();
    ASSERT_EQ(run(std::string("simulate --trajectory builtin:short --seed 3 --season ") + season +
                  " --out " + sim)
                  .code,
              0);
    const CliResult r = run("describe --method sc --poses " + sim + "/poses_history_file.txt" +
                            " --points " + sim + "/pts_history_file.txt --out " + sim + "/sc");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(sim + "/sc/frames.txt"));
  }
  const std::string summer = (d / "summer").string(), fall = (d / "fall").string();
  const std::string db = (d / "map.db").string();
  CliResult r =
      run("db build --signatures " + summer + "/sc --gt " + summer + "/gt.txt --out " + db);
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("db query --db " + db + " --signatures " + fall + "/sc --gt " + fall +
          "/gt.txt --exact --k 3 --out " + (d / "q").string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run("evaluate --method sc --signatures " + fall + "/sc --gt " + fall + "/gt.txt --against " +
          summer + "/sc --gt2 " + summer + "/gt.txt --out " + (d / "ev").string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json online, offline;
  std::ifstream(d / "q/metrics.json") >> online;
  std::ifstream(d / "ev/metrics.json") >> offline;
  // Exact database queries against the whole map are the offline difference-matrix rows.
  EXPECT_NEAR(online["auc"].get<double>(), offline["auc"].get<double>(), 1e-6);
  EXPECT_EQ(online["n_gt_loops"], offline["n_gt_loops"]);
  std::ifstream csv(d / "q/candidates.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "query_id,rank,session,keyframe,distance,yaw_deg,mirrored");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 3 * online["n_queries"].get<int>());
  EXPECT_FALSE(has_temp_files(d));

  // Bad input: a damaged database, a --gt count that does not match.
  std::string bytes;
  {
    std::ifstream in(db, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 4);
  write(d / "bad.db", bytes);
  r = run("db query --db " + (d / "bad.db").string() + " --signatures " + fall + "/sc --out " +
          (d / "q2").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("checksum"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(d / "q2" / "candidates.csv"));
  r = run("db build --signatures " + summer + "/sc --signatures " + fall + "/sc --gt " + summer +
          "/gt.txt --out " + (d / "x.db").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(fs::exists(d / "x.db"));
}

TEST(Cli, RenderWritesTheKittiOdometryLayout) {
  const fs::path d = temp_dir("render");
  const CliResult r =
      run("render --trajectory builtin:short --season winter --seed 3 --scale 0.25 "
          "--first 10 --frames 3 --out " +
          (d / "seq").string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (int cam = 0; cam < 2; ++cam) {
    for (int i = 0; i < 3; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "image_%d/%06d.png", cam, i);
      EXPECT_TRUE(fs::exists(d / "seq" / name)) << name;
    }
  }
  std::ifstream calib(d / "seq/calib.txt");
  std::string p0, p1;
  std::getline(calib, p0);
  std::getline(calib, p1);
  EXPECT_EQ(p0.rfind("P0: ", 0), 0u);
  std::istringstream line(p1.substr(4));
  double v[12];
  for (double& x : v) line >> x;
  EXPECT_NEAR(v[3], -386.1448 * 0.25, 1e-6);  // -fx * baseline
  int poses = 0, times = 0;
  std::string l;
  for (std::ifstream in(d / "seq/poses.txt"); std::getline(in, l);) ++poses;
  for (std::ifstream in(d / "seq/times.txt"); std::getline(in, l);) ++times;
  EXPECT_EQ(poses, 3);
  EXPECT_EQ(times, 3);
  EXPECT_FALSE(has_temp_files(d));
  EXPECT_EQ(run("render --trajectory builtin:short --scale 0 --out " + (d / "x").string()).code, 2);

  // The reader a VO starts from.
  const io::KittiSequence seq = io::open_kitti_sequence((d / "seq").string());
  EXPECT_EQ(seq.frames(), 3u);
  EXPECT_NEAR(seq.calib.fx, 718.856 * 0.25, 1e-6);
  EXPECT_NEAR(seq.calib.baseline_m, 386.1448 / 718.856, 1e-9);
  const io::GrayPng left = io::read_png_gray(seq.left(2));
  EXPECT_EQ(left.width, 310);
  EXPECT_EQ(left.height, 94);
  // The InputError message of `load`, or "accepted".
  auto error_of = [](auto&& load) {
    try {
      load();
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string dir = (d / "seq").string();
  fs::remove(d / "seq/image_1/000001.png");
  const std::string missing = error_of([&] { io::open_kitti_sequence(dir); });
  EXPECT_NE(missing.find("image_1/000001.png"), std::string::npos) << missing;
  write(d / "seq/calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 x 0 1 0 0 0 0 1 0\n");
  const std::string junk = error_of([&] { io::read_kitti_calib(dir + "/calib.txt"); });
  EXPECT_NE(junk.find("calib.txt:2"), std::string::npos) << junk;
  write(d / "seq/calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_THROW(io::read_kitti_calib((d / "seq/calib.txt").string()), io::InputError);
}


TEST(Cli, VoAndRunFromRenderedImages) {
  const fs::path d = temp_dir("vo");
  const std::string seq = (d / "seq").string();
  ASSERT_EQ(run("render --trajectory builtin:short --scale 0.25 --frames 30 --out " + seq).code, 0);
  const CliResult vo =
      run("vo --kitti " + seq + " --out " + (d / "vo").string() + " --segments 10 20 --quiet");
  ASSERT_EQ(vo.code, 0) << vo.output;
  EXPECT_NE(vo.output.find("fps"), std::string::npos) << vo.output;
  EXPECT_NE(vo.output.find("translation"), std::string::npos) << vo.output;
  for (const char* f : {"poses_history_file.txt", "pts_history_file.txt", "trajectory.txt", "vo.json"})
    EXPECT_TRUE(fs::exists(d / "vo" / f)) << f;
  std::ifstream json_in(d / "vo/vo.json");
  const nlohmann::json j = nlohmann::json::parse(json_in);
  EXPECT_EQ(j["frames"].get<int>(), 30);
  EXPECT_GT(j["metrics"]["segments"].get<int>(), 0);
  EXPECT_LT(j["metrics"]["translation_percent"].get<double>(), 5.0);
  EXPECT_GT(j["fps"].get<double>(), 0.0);
  // `describe` reads the VO's SO-DSO history unchanged.
  const CliResult described = run("describe --method sc --poses " + (d / "vo/poses_history_file.txt").string() +
                                  " --points " + (d / "vo/pts_history_file.txt").string() +
                                  " --out " + (d / "sc").string());
  EXPECT_EQ(described.code, 0) << described.output;
  EXPECT_TRUE(fs::exists(d / "sc/signatures.txt"));
  // Blank frames: an explicit reset, reported in vo.json.
  ASSERT_EQ(run("vo --kitti " + seq + " --out " + (d / "vo_blank").string() +
                " --quiet --blank-frames 12 13")
                .code,
            0);
  std::ifstream blank_in(d / "vo_blank/vo.json");
  const nlohmann::json b = nlohmann::json::parse(blank_in);
  ASSERT_FALSE(b["reset_frames"].empty());
  EXPECT_EQ(b["reset_frames"][0].get<int>(), 12);
  // run: VO + describe + evaluate + report.
  const CliResult all = run("run --kitti " + seq + " --out " + (d / "run").string() +
                            " --methods sc delight --segments 10 --quiet");
  ASSERT_EQ(all.code, 0) << all.output;
  for (const char* f : {"report.html", "summary.json", "vo/vo.json", "sc/signatures.txt",
                        "delight/signatures.txt"})
    EXPECT_TRUE(fs::exists(d / "run" / f)) << f;
  std::ifstream summary_in(d / "run/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  ASSERT_EQ(summary["methods"].size(), 2u);
  for (const nlohmann::json& m : summary["methods"]) {
    // 30 m are too short for the imitation's warm-up plus the 100-keyframe mask: nothing to score.
    EXPECT_EQ(m["evaluated"].get<bool>(), m["places"].get<int>() > 0);
    EXPECT_EQ(fs::exists(d / "run" / m["method"].get<std::string>() / "metrics.json"),
              m["evaluated"].get<bool>());
  }
  EXPECT_FALSE(has_temp_files(d));
  // Bad input: exit code 2, the file named, nothing written.
  const CliResult missing = run("vo --kitti " + (d / "nope").string() + " --out " + (d / "x").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("nope"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(d / "x"));
  EXPECT_EQ(run("vo --kitti " + seq + " --points 0 --out " + (d / "y").string()).code, 2);
  EXPECT_EQ(run("run --kitti " + seq + " --methods sc nope --out " + (d / "y").string()).code, 2);
  EXPECT_EQ(run("run --kitti " + seq + " --methods bow --out " + (d / "y").string()).code, 2);
  EXPECT_FALSE(fs::exists(d / "y"));
  write(d / "seq/poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  const CliResult short_gt = run("vo --kitti " + seq + " --out " + (d / "z").string());
  EXPECT_EQ(short_gt.code, 2);
  EXPECT_NE(short_gt.output.find("poses.txt:2"), std::string::npos) << short_gt.output;
  EXPECT_FALSE(fs::exists(d / "z"));
}


TEST(Cli, ImageBaselinesDescribeAndEvaluateTheSameKeyframes) {
  const fs::path d = temp_dir("images");
  const std::string seq = (d / "seq").string();
  ASSERT_EQ(run("render --trajectory builtin:short --scale 0.5 --frames 12 --out " + seq).code, 0);
  // Keyframes to describe: every other frame, as a describe output lists them.
  fs::create_directories(d / "kf");
  write(d / "kf/incoming_id_file.txt", "0\n2\n4\n6\n8\n10\n");
  const CliResult voc = run("vocab train --kitti " + seq + " --step 3 --k 4 --depth 3 --features 500 --out " +
                            (d / "voc.bin").string());
  ASSERT_EQ(voc.code, 0) << voc.output;
  ASSERT_EQ(run("vocab train --kitti " + seq + " --step 3 --k 4 --depth 3 --features 500 --text --out " +
                (d / "voc.txt").string()).code, 0);
  for (const std::string& m : {std::string("gist"), std::string("bow")}) {
    const std::string vocab = m == "bow" ? " --vocab " + (d / "voc.txt").string() : "";
    const CliResult desc = run("describe --method " + m + " --kitti " + seq + " --keyframes " +
                               (d / "kf").string() + vocab + " --out " + (d / m).string());
    ASSERT_EQ(desc.code, 0) << desc.output;
    EXPECT_EQ(read_lines(d / m / "incoming_id_file.txt").size(), 6u);
    const CliResult ev = run("evaluate --method " + m + " --signatures " + (d / m).string() +
                             " --gt " + seq + "/poses.txt --mask 3 --threshold 3 --out " +
                             (d / m / "eval").string());
    ASSERT_EQ(ev.code, 0) << ev.output;
    std::ifstream in(d / m / "eval/metrics.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["n_queries"].get<int>(), 6);
    EXPECT_EQ(j["method"].get<std::string>(), m);
  }
  EXPECT_EQ(read_lines(d / "gist/signatures.txt").size(), 6u);
  // GIST on two threads: the same descriptors.
  ASSERT_EQ(run("describe --method gist --threads 2 --kitti " + seq + " --keyframes " +
                (d / "kf").string() + " --out " + (d / "gist2").string()).code, 0);
  EXPECT_EQ(read_lines(d / "gist2/signatures.txt"), read_lines(d / "gist/signatures.txt"));
  EXPECT_EQ(read_lines(d / "bow/bow.txt").size(), 6u);
  // Bad input: no vocabulary, a keyframe beyond the sequence, a damaged bow.txt.
  EXPECT_EQ(run("describe --method bow --kitti " + seq + " --keyframes " + (d / "kf").string() +
                " --out " + (d / "x").string()).code, 2);
  fs::create_directories(d / "kf2");
  write(d / "kf2/incoming_id_file.txt", "0\n99\n");
  const CliResult beyond = run("describe --method gist --kitti " + seq + " --keyframes " +
                               (d / "kf2").string() + " --out " + (d / "y").string());
  EXPECT_EQ(beyond.code, 2);
  EXPECT_NE(beyond.output.find("99"), std::string::npos) << beyond.output;
  EXPECT_FALSE(fs::exists(d / "y"));
  write(d / "bow/bow.txt", "1 0.5 3 0.5\n4 0.25 2 0.75\n");
  const CliResult bad = run("evaluate --method bow --signatures " + (d / "bow").string() + " --gt " +
                            seq + "/poses.txt --out " + (d / "z").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("bow.txt:2"), std::string::npos) << bad.output;
  EXPECT_FALSE(has_temp_files(d));
}

}  // namespace
}  // namespace loopscan
