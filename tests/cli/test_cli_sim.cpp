// The `loopscan` CLI: simulate, the place database and render.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/io/png.hpp"
#include "loopscan/io/sodso.hpp"

#include "cli/cli_support.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

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
  // Each step ends with a summary line of its own: items and time.
  const std::size_t keyframes = read_lines(d / "sim/poses_history_file.txt").size();
  EXPECT_NE(r2.output.find("describe sc: " + std::to_string(keyframes) + " keyframes in "),
            std::string::npos)
      << r2.output;
  const std::size_t places = read_lines(d / "sc/incoming_id_file.txt").size();
  EXPECT_NE(r3.output.find("evaluate sc: " + std::to_string(2 * places) +  // adaptive: 2 passes
                           " difference-matrix rows in "),
            std::string::npos)
      << r3.output;
  // Metrics by direction of the revisit: the two classes share the loops.
  nlohmann::json metrics;
  std::ifstream(d / "eval/metrics.json") >> metrics;
  EXPECT_EQ(metrics["fusion"], "adaptive");  // default mode's fusion
  EXPECT_TRUE(metrics.contains("fusion_weights"));
  const auto& by = metrics["by_direction"];
  EXPECT_EQ(by["same"]["n_loops"].get<int>() + by["opposite"]["n_loops"].get<int>(),
            metrics["n_gt_loops"].get<int>());
  EXPECT_LE(by["same"]["top1_correct"].get<int>(), by["same"]["n_loops"].get<int>());

  // Two-sided scans in the centroid frame: every keyframe gets a place (no INIT_FRAME gap).
  const std::string vo = " --poses " + (d / "sim/poses_history_file.txt").string() + " --points " +
                         (d / "sim/pts_history_file.txt").string();
  const std::string two_sided =
      config(d, "two_sided",
             "imitation:\n  lookahead_m: 20\ndescriptors:\n  scan_context:\n    frame: centroid\n");
  const CliResult r4 =
      run("describe --method sc" + two_sided + vo + " --out " + (d / "sc2").string());
  ASSERT_EQ(r4.code, 0) << r4.output;
  EXPECT_EQ(read_lines(d / "sc2/incoming_id_file.txt").size(),
            read_lines(d / "sim/poses_history_file.txt").size());
  const CliResult r5 =
      run("evaluate --method sc --fusion adaptive --signatures " + (d / "sc2").string() + " --gt " +
          (d / "sim/gt.txt").string() + " --out " + (d / "eval2").string());
  ASSERT_EQ(r5.code, 0) << r5.output;
  std::ifstream(d / "eval2/metrics.json") >> metrics;
  EXPECT_TRUE(metrics.contains("fusion_weights"));
  EXPECT_EQ(run("evaluate --method sc" +
                config(d, "nan_weight", "evaluation:\n  structure_weight: nan\n") +
                " --signatures " + (d / "sc2").string() + " --gt " + (d / "sim/gt.txt").string() +
                " --out " + (d / "bad").string())
                .code,
            2);
  // Mistakes: an unknown frame; reference mode is the paper's forward-only scan in PCA.
  const std::string sc = "descriptors:\n  scan_context:\n";
  for (const std::string& bad :
       {config(d, "b1", sc + "    frame: gravity\n"),
        " --mode reference" + config(d, "b2", "imitation:\n  lookahead_m: 10\n"),
        " --mode reference" + config(d, "b3", sc + "    frame: camera\n"),
        config(d, "b4", "imitation:\n  lookahead_m: -1\n"),
        config(d, "b5", "imitation:\n  lookahead_m: nan\n"),
        config(d, "b6", sc + "    frame: camera\n    lateral_offset_m: .inf\n")}) {
    const CliResult r6 = run("describe --method sc" + bad + vo + " --out " + (d / "bad").string());
    EXPECT_EQ(r6.code, 2) << bad << ": " << r6.output;
    EXPECT_FALSE(fs::exists(d / "bad")) << bad;
  }
}

TEST(Cli, SimulateLapsDrivesTheRouteAgainWithNewVoNoise) {
  const fs::path d = temp_dir("simulate_laps");
  ASSERT_EQ(run("simulate --trajectory builtin:short --out " + (d / "one").string()).code, 0);
  const std::string drift = config(d, "drift",
                                   "simulator:\n  vo:\n    drift_translation_per_m: 0.02\n"
                                   "    drift_rotation_deg_per_m: 0.06\n");
  const CliResult r = run("simulate --trajectory builtin:short --laps 2" + drift + " --out " +
                          (d / "two").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const auto one = io::read_kitti_poses((d / "one/gt.txt").string());
  const auto two = io::read_kitti_poses((d / "two/gt.txt").string());
  // Lap, connector back to the start, the same lap again.
  const std::size_t n = one.size(), lap = two.size() - n;
  ASSERT_GT(lap, n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(two[i].isApprox(one[i], 1e-6)) << i;
    ASSERT_TRUE(two[lap + i].isApprox(one[i], 1e-6)) << i;
  }
  // The VO's noise is new each lap: its error of the motion between the same two frames differs.
  const std::vector<KeyframePose> vo =
      io::read_sodso_poses((d / "two/poses_history_file.txt").string());
  std::map<int, Eigen::Isometry3d> T_vo_cam_world;
  for (const KeyframePose& k : vo) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.matrix().topRows<3>() = k.T_cam_world;
    T_vo_cam_world[k.id] = T;
  }
  auto motion_error = [&](int a, int b) -> Eigen::Vector3d {
    Eigen::Isometry3d A = Eigen::Isometry3d::Identity(), B = Eigen::Isometry3d::Identity();
    A.matrix().topRows<3>() = two[static_cast<std::size_t>(a)];
    B.matrix().topRows<3>() = two[static_cast<std::size_t>(b)];
    const Eigen::Isometry3d vo_motion = T_vo_cam_world[a] * T_vo_cam_world[b].inverse();
    return (vo_motion.inverse() * (A.inverse() * B)).translation();
  };
  int compared = 0;
  double largest_difference = 0;
  for (auto it = T_vo_cam_world.begin(); std::next(it) != T_vo_cam_world.end(); ++it) {
    const int a = it->first, b = std::next(it)->first, offset = static_cast<int>(lap);
    if (b >= static_cast<int>(n) || !T_vo_cam_world.count(a + offset) ||
        !T_vo_cam_world.count(b + offset))
      continue;
    ++compared;
    largest_difference = std::max(
        largest_difference, (motion_error(a + offset, b + offset) - motion_error(a, b)).norm());
  }
  EXPECT_GT(compared, static_cast<int>(n) / 3);
  EXPECT_GT(largest_difference, 1e-3);
  // A season per lap: the same VO, each keyframe's points those of its lap's season (a
  // connector belongs to the lap it leads into).
  for (const char* season : {"summer", "winter", "summer,winter"}) {
    const CliResult rs = run("simulate --trajectory builtin:short --laps 2 --season " +
                             std::string(season) + drift + " --out " + (d / season).string());
    ASSERT_EQ(rs.code, 0) << rs.output;
  }
  EXPECT_EQ(read_lines(d / "summer,winter/poses_history_file.txt"),
            read_lines(d / "summer/poses_history_file.txt"));
  EXPECT_EQ(read_lines(d / "winter/poses_history_file.txt"),
            read_lines(d / "summer/poses_history_file.txt"));
  auto points_of = [&](const char* season, bool second_lap) {
    std::vector<std::string> out;
    for (const std::string& line : read_lines(d / season / "pts_history_file.txt"))
      if ((std::stoi(line) >= static_cast<int>(n)) == second_lap) out.push_back(line);
    return out;
  };
  std::vector<std::string> expected = points_of("summer", false);
  const std::vector<std::string> winter = points_of("winter", true);
  expected.insert(expected.end(), winter.begin(), winter.end());
  EXPECT_EQ(read_lines(d / "summer,winter/pts_history_file.txt"), expected);
  EXPECT_NE(points_of("summer", true), winter);  // the seasons do differ
  // Mistakes: no lap, a VO of one drive with laps, seasons without laps or unknown.
  for (const auto& [bad, named] : std::vector<std::pair<std::string, std::string>>{
           {" --laps 0", "--laps"},
           {" --laps 1.5", "--laps"},
           {" --laps 2 --vo-poses " + (d / "one/poses_history_file.txt").string(), "--vo-poses"},
           {" --season summer,winter", "--season"},
           {" --laps 2 --season summer,monsoon", "monsoon"}}) {
    const CliResult e =
        run("simulate --trajectory builtin:short" + bad + " --out " + (d / "bad").string());
    EXPECT_NE(e.code, 0) << bad;
    EXPECT_NE(e.output.find(named), std::string::npos) << e.output;
    EXPECT_FALSE(fs::exists(d / "bad")) << bad;
  }
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
  const std::string n_summer =
      std::to_string(read_lines(summer + "/sc/incoming_id_file.txt").size());
  const std::string n_fall = std::to_string(read_lines(fall + "/sc/incoming_id_file.txt").size());
  EXPECT_NE(r.output.find("db build: session 0: " + n_summer + " places in "), std::string::npos)
      << r.output;
  r = run("db query --db " + db + " --signatures " + fall + "/sc --gt " + fall +
          "/gt.txt --exact --k 3 --out " + (d / "q").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("db query: " + n_fall + " queries in "), std::string::npos) << r.output;
  // The database fuses each query on its own, like the paper: compare with that fusion.
  r = run("evaluate --method sc --fusion fused --signatures " + fall + "/sc --gt " + fall +
          "/gt.txt --against " + summer + "/sc --gt2 " + summer + "/gt.txt --out " +
          (d / "ev").string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json online, offline;
  std::ifstream(d / "q/metrics.json") >> online;
  std::ifstream(d / "ev/metrics.json") >> offline;
  // The database fuses per query; adaptive fusion needs the whole matrix: refused, exit 2.
  EXPECT_EQ(run("db build" + config(d, "adaptive", "database:\n  fusion: adaptive\n") +
                " --signatures " + summer + "/sc --out " + (d / "bad.db").string())
                .code,
            2);
  EXPECT_FALSE(fs::exists(d / "bad.db"));
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

  // Compact storage: a file ~3.4x smaller, the same answers up to the rounding.
  const std::string compact = (d / "compact.db").string();
  r = run("db build" + config(d, "compact", "database:\n  storage: compact\n") + " --signatures " +
          summer + "/sc --gt " + summer + "/gt.txt --out " + compact);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_GT(fs::file_size(db), 3 * fs::file_size(compact));
  r = run("db query --db " + compact + " --signatures " + fall + "/sc --gt " + fall +
          "/gt.txt --exact --k 3 --out " + (d / "qc").string());
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json small;
  std::ifstream(d / "qc/metrics.json") >> small;
  EXPECT_EQ(small["storage"], "compact");
  EXPECT_NEAR(small["auc"].get<double>(), online["auc"].get<double>(), 0.01);

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

// builtin:reverse drives a street east, then west in the other lane: the places described
// from the next lanes (descriptors.scan_context.lateral_offset_m) make db query recognise the
// reverse drive, and so do the default lateral versions.
TEST(Cli, DbQueryWithLaneVersionsRecognisesAReverseDrive) {
  const fs::path d = temp_dir("reverse");
  const std::string sim = (d / "sim").string();
  ASSERT_EQ(run("simulate --trajectory builtin:reverse --season summer --seed 3 --out " + sim).code,
            0);
  const std::string vo = " --method sc --poses " + sim + "/poses_history_file.txt --points " + sim +
                         "/pts_history_file.txt";
  const std::string two_sided = "imitation:\n  lookahead_m: 20\n";
  for (const std::string off : {"0", "-3.5", "3.5"}) {  // one descriptor each, no versions
    const std::string lane =
        config(d, "lane" + off,
               two_sided + "descriptors:\n  scan_context:\n    lateral_offset_m: " + off +
                   "\n    lateral_versions_m: []\n");
    const CliResult r = run("describe" + vo + lane + " --out " + (d / off).string());
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const CliResult described = run("describe" + vo + config(d, "versions", two_sided) + " --out " +
                                  (d / "versions").string());
  ASSERT_EQ(described.code, 0) << described.output;  // the default lateral versions
  ASSERT_EQ(run("db build --signatures " + (d / "0").string() + " --gt " + sim + "/gt.txt --out " +
                (d / "map.db").string())
                .code,
            0);
  auto opposite_top1 = [&](const std::string& lanes, int& loops, const std::string& queries = "0") {
    const fs::path out = d / ("q" + queries + std::to_string(lanes.size()));
    const CliResult r = run("db query --db " + (d / "map.db").string() + " --signatures " +
                            (d / queries).string() + lanes + " --exact --k 1 --same-session " +
                            "--gt " + sim + "/gt.txt --out " + out.string());
    EXPECT_EQ(r.code, 0) << r.output;
    nlohmann::json m;
    std::ifstream(out / "metrics.json") >> m;
    loops = m["by_direction"]["opposite"]["n_loops"].get<int>();
    return m["by_direction"]["opposite"]["top1_correct"].get<int>();
  };
  int loops = 0;
  const int without = opposite_top1("", loops);
  const int with =
      opposite_top1(" --lanes " + (d / "-3.5").string() + " " + (d / "3.5").string(), loops);
  ASSERT_GT(loops, 50);
  EXPECT_GE(with, 0.4 * loops) << with << " of " << loops;
  EXPECT_GE(with, 2 * without) << without << " without lane versions";
  // The default lateral versions (one signature, five rows) do it without separate files.
  const int versions = opposite_top1("", loops, "versions");
  EXPECT_GE(versions, 0.4 * loops) << versions << " of " << loops;
  EXPECT_GE(versions, 2 * without) << without << " without lateral versions";
  // A lane version must describe the same places.
  EXPECT_EQ(run("db query --db " + (d / "map.db").string() + " --signatures " + (d / "0").string() +
                " --lanes " + sim + " --out " + (d / "bad").string())
                .code,
            2);
}

// The demo's report draws a reverse revisit the bird's-eye place recognises at top-1, with the
// pose its image search found; the drawn pose agrees with the truth its caption states.
TEST(Cli, DemoDrawsAReverseRevisitOfTheBirdsEyePlace) {
  const fs::path d = temp_dir("demo-reverse");
  const CliResult r = run("demo --trajectory builtin:reverse --out " + (d / "demo").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string page = file_bytes(d / "demo/report/index.html");
  const std::size_t at = page.find("recognises a reverse revisit: return, keyframe ");
  ASSERT_NE(at, std::string::npos);
  int query = 0, place = 0, right = 0, total = 0, top1 = 0, loops = 0;
  double x = 0, z = 0, yaw = 0, tx = 0, tz = 0, tyaw = 0;
  ASSERT_EQ(
      std::sscanf(page.c_str() + at,
                  "recognises a reverse revisit: return, keyframe %d finds first drive, "
                  "keyframe %d at top-1, and its image search puts it at x %lf m, z %lf m, "
                  "yaw %lf degrees (truth %lf, %lf, %lf). %d of %d opposite-direction "
                  "revisits of the summer drive are right at top-1 with this one "
                  "descriptor a place; of the %d driven more than 150 degrees apart, the "
                  "found pose is within 2 m and 10 degrees of the truth for %d",
                  &query, &place, &x, &z, &yaw, &tx, &tz, &tyaw, &top1, &loops, &total, &right),
      12)
      << page.substr(at, 400);
  EXPECT_GT(query, place);
  EXPECT_LT(std::hypot(x - tx, z - tz), 2.0);
  EXPECT_LT(std::abs(std::remainder(yaw - tyaw, 360.0)), 10.0);
  EXPECT_GT(loops, 20);
  EXPECT_GE(top1, 0.5 * loops) << top1 << " of " << loops;  // one descriptor a place
  EXPECT_LE(total, top1);
  EXPECT_GE(right, 1);
  EXPECT_LE(right, total);
  bool figure = false;
  for (const auto& f : fs::directory_iterator(d / "demo/report/figures")) {
    if (f.path().filename().string().find("bird-s-eye-place") == std::string::npos) continue;
    const std::string svg = file_bytes(f.path());
    figure = svg.find("the pose found") != std::string::npos &&
             svg.find("true pose") != std::string::npos &&
             svg.find("(the query)") != std::string::npos;
  }
  EXPECT_TRUE(figure);
  fs::remove_all(d);
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
      char name[64];  // room for any two ints: no truncation warning
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

}  // namespace
}  // namespace loopscan
