// `loopscan close`: its files on a simulated drive with a drifting VO, the library's online
// closer giving the same poses, a second session in the saved map, and bad input refused with
// nothing written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli/cli_support.hpp"
#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/io/sodso.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using test::fs::path;

// A drifting VO on the short built-in route (summer, and a winter session of it).
const path& drives() {
  static const path dir = [] {
    // One folder a process: ctest runs the cases of this file in parallel processes.
    const path d = test::temp_dir("close_" + std::to_string(getpid()));
    for (const char* season : {"summer", "winter"}) {
      const std::string drift =
          test::config(d, "drift",
                       "simulator:\n  vo:\n    drift_translation_per_m: 0.02\n"
                       "    drift_rotation_deg_per_m: 0.06\n");
      const test::CliResult r = test::run(
          "simulate --trajectory builtin:short" + drift + " --season " + std::string(season) +
          " --session " + (season[0] == 's' ? "1" : "7") + " --out " + (d / season).string());
      EXPECT_EQ(r.code, 0) << r.output;
    }
    return d;
  }();
  return dir;
}

std::string close_args(const std::string& session, const path& out) {
  const path s = drives() / session;
  return "close --quiet --poses " + (s / "poses_history_file.txt").string() + " --points " +
         (s / "pts_history_file.txt").string() + " --gt " + (s / "gt.txt").string() + " --out " +
         out.string();
}

TEST(CliClose, WritesCorrectedPosesLoopsAndMetricsEqualToTheOnlineCloser) {
  const path out = drives() / "out";
  const test::CliResult r = test::run(close_args("summer", out) + " --write-points");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = nlohmann::json::parse(test::file_bytes(out / "metrics.json"));
  EXPECT_GT(m["loops"]["accepted"].get<int>(), 0);
  EXPECT_EQ(m["loops"]["false_accepted"].get<int>(), 0);
  EXPECT_LT(m["ate_after_m"].get<double>(), m["ate_before_m"].get<double>());
  // What a live system budgets: the latency of one keyframe into the closer, memory, places.
  const nlohmann::json& latency = m["add_keyframe_latency_ms"];
  EXPECT_GT(latency["p50"].get<double>(), 0);
  EXPECT_LE(latency["p50"].get<double>(), latency["p99"].get<double>());
  EXPECT_LE(latency["p99"].get<double>(), latency["max"].get<double>());
  // Samples of the whole run's time: at most half of them reach twice their mean (Markov).
  EXPECT_LE(latency["p50"].get<double>(), 2 * m["ms_per_keyframe"]["total"].get<double>());
  EXPECT_GT(m["peak_memory_mb"].get<double>(), 1);
  // Revisit keyframes link to the places the map holds; the others join it.
  EXPECT_GT(m["linked_keyframes"].get<int>(), 0);
  EXPECT_EQ(m["map_places"].get<int>() + m["linked_keyframes"].get<int>(),
            m["described"].get<int>());
  // The short drive revisits its first street: those keyframes are the revisits, some closed.
  EXPECT_GT(m["loops"]["revisit_keyframes"].get<int>(), 10);
  EXPECT_GT(m["loops"]["revisits_closed"].get<int>(), 0);
  EXPECT_LE(m["loops"]["revisits_closed"].get<int>(), m["loops"]["revisit_keyframes"].get<int>());
  // The same graph given every revisit's true relative pose undoes most of the drift.
  EXPECT_LT(m["ate_given_true_loops_m"].get<double>(), 0.5 * m["ate_before_m"].get<double>());
  // So do its own loops made exact (not a bound on ate_after_m: the reference's fixed 0.1 m and
  // 0.5 degrees weigh the loops against the odometry otherwise than measured covariances).
  EXPECT_LT(m["ate_given_exact_accepted_loops_m"].get<double>(),
            0.5 * m["ate_before_m"].get<double>());
  // Without linking every described keyframe is a place; the revisits are the same keyframes.
  const path copies = drives() / "copies";
  const test::CliResult rc =
      test::run(close_args("summer", copies) +
                test::config(drives(), "copies", "closure:\n  lifelong:\n    enabled: false\n"));
  ASSERT_EQ(rc.code, 0) << rc.output;
  const nlohmann::json mc = nlohmann::json::parse(test::file_bytes(copies / "metrics.json"));
  EXPECT_EQ(mc["map_places"].get<int>(), mc["described"].get<int>());
  EXPECT_EQ(mc["linked_keyframes"].get<int>(), 0);
  EXPECT_EQ(mc["loops"]["revisit_keyframes"], m["loops"]["revisit_keyframes"]);
  for (const char* key : {"scan", "describe", "cloud", "query", "verify", "graph", "total"}) {
    EXPECT_TRUE(m["ms_per_keyframe"].contains(key)) << key;
  }
  const std::vector<std::string> csv = test::read_lines(out / "loops.csv");
  ASSERT_GE(csv.size(), 2u);
  EXPECT_EQ(csv[0].rfind("query,match,session,r00,r01,r02,tx,", 0), 0u) << csv[0];
  EXPECT_NE(csv[0].find(",overlap,rmse,accepted,"), std::string::npos);
  EXPECT_NE(csv[0].find(",true,"), std::string::npos);
  for (const char* f : {"trajectory.svg", "map.db", "pts_closed.txt"}) {
    EXPECT_TRUE(test::fs::exists(out / f)) << f;
  }

  // The library, streaming the same files, gives the same corrected poses.
  const path s = drives() / "summer";
  const std::vector<KeyframePose> poses =
      io::read_sodso_poses((s / "poses_history_file.txt").string());
  const std::vector<IdPoint> points = io::read_sodso_points((s / "pts_history_file.txt").string());
  closure::LoopCloser closer(closure::LoopCloserConfig::make(Method::ScanContext));
  for_each_keyframe(poses, points, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    closer.add_keyframe(k, p, n);
  });
  closer.finish();
  const std::vector<KeyframePose> online = closer.corrected_poses();
  const std::vector<KeyframePose> written =
      io::read_sodso_poses((out / "poses_closed.txt").string());
  ASSERT_EQ(online.size(), written.size());
  for (std::size_t i = 0; i < online.size(); ++i) {
    EXPECT_EQ(online[i].id, written[i].id);
    EXPECT_LT((online[i].T_cam_world - written[i].T_cam_world).cwiseAbs().maxCoeff(), 1e-6);
  }
  EXPECT_EQ(test::read_lines(out / "trajectory_closed.txt").size(), poses.size());
}

TEST(CliClose, ASecondSessionIsPlacedInTheSavedMap) {
  const path map_out = drives() / "map";
  ASSERT_EQ(test::run(close_args("summer", map_out)).code, 0);
  // Candidates aligned and places classified on 3 threads: the same loops and map.
  const path threaded = drives() / "map_threaded";
  ASSERT_EQ(test::run(close_args("summer", threaded) +
                      test::config(drives(), "threaded", "closure:\n  threads: 3\n"))
                .code,
            0);
  for (const char* f : {"map.db", "loops.csv", "poses_closed.txt"}) {
    EXPECT_TRUE(test::file_bytes(threaded / f) == test::file_bytes(map_out / f)) << f;
  }
  const nlohmann::json mt = nlohmann::json::parse(test::file_bytes(threaded / "metrics.json"));
  EXPECT_EQ(mt["threads"].get<int>(), 3);
  EXPECT_GT(mt["map_clouds_ms"].get<double>(), 0);
  const path out = drives() / "winter_out";
  const test::CliResult r =
      test::run(close_args("winter", out) + " --map " + (map_out / "map.db").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("in the map's frame from keyframe"), std::string::npos) << r.output;
  const nlohmann::json m = nlohmann::json::parse(test::file_bytes(out / "metrics.json"));
  EXPECT_TRUE(m["anchored_to_map"].get<bool>());
  EXPECT_EQ(m["session"].get<int>(), 1);
  EXPECT_EQ(m["loops"]["false_accepted"].get<int>(), 0);
  EXPECT_GT(m["map_places"].get<int>(), 250);  // both sessions
  // True loops into the (corrected) map hold the session in the map's frame.
  EXPECT_LT(m["ate_given_true_loops_m"].get<double>(), m["ate_before_m"].get<double>());
}

TEST(CliClose, WithoutLoopsTheExactLoopsReferenceIsTheVoItself) {
  const path out = drives() / "none_closed";
  const test::CliResult r = test::run(
      close_args("summer", out) +
      test::config(drives(), "none_closed",
                   "closure:\n  max_candidate_distance: -1000\n  proximity:\n    candidates: 0\n"));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = nlohmann::json::parse(test::file_bytes(out / "metrics.json"));
  ASSERT_EQ(m["loops"]["revisits_closed"].get<int>(), 0);
  EXPECT_GT(m["loops"]["revisit_keyframes"].get<int>(), 10);
  EXPECT_LT(m["ate_given_true_loops_m"].get<double>(), 0.5 * m["ate_before_m"].get<double>());
  // No loop to make exact: only odometry edges, at rest at the VO's poses (orthonormalised:
  // within a millimetre).
  EXPECT_NEAR(m["ate_given_exact_accepted_loops_m"].get<double>(), m["ate_before_m"].get<double>(),
              1e-3);
}

TEST(CliClose, BadInputIsRefusedWithNothingWritten) {
  const path map_out = drives() / "map_for_errors";
  ASSERT_EQ(test::run(close_args("summer", map_out)).code, 0);
  const path dir = test::temp_dir("close_bad_" + std::to_string(getpid()));
  // A truncated map.
  const std::string map = test::file_bytes(map_out / "map.db");
  test::write(dir / "cut.db", map.substr(0, map.size() / 2));
  test::CliResult r =
      test::run(close_args("winter", dir / "o1") + " --map " + (dir / "cut.db").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("cut.db"), std::string::npos) << r.output;
  // A map of another method: the flag contradicts the map, both named.
  r = test::run(close_args("winter", dir / "o2") + " --method m2dp --map " +
                (map_out / "map.db").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("conflicting methods: --method says m2dp"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("map.db says sc"), std::string::npos) << r.output;
  // A pose with NaN.
  std::vector<std::string> lines = test::read_lines(drives() / "summer" / "poses_history_file.txt");
  lines[5] = "10 1 0 0 nan 0 1 0 0 0 0 1 0";
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  test::write(dir / "poses.txt", text);
  r = test::run("close --quiet --poses " + (dir / "poses.txt").string() + " --points " +
                (drives() / "summer" / "pts_history_file.txt").string() + " --out " +
                (dir / "o3").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("poses.txt:6"), std::string::npos) << r.output;
  // No thread to close with: the configuration file's line is named.
  r = test::run(close_args("summer", dir / "o4") +
                test::config(dir, "no_threads", "closure:\n  threads: 0\n"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("no_threads"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("threads"), std::string::npos) << r.output;
  for (const char* o : {"o1", "o2", "o3", "o4"}) EXPECT_FALSE(test::fs::exists(dir / o)) << o;
  EXPECT_FALSE(test::has_temp_files(dir));
}

TEST(CliSlam, RunsTheVoThenClosesLoopsOnRealKittiImages) {
  const path seq = path(test::shared_dir()) / "data/real/kitti06-000000-000050";
  LOOPSCAN_SKIP_WITHOUT_SHARED(test::fs::exists(seq / "calib.txt"), seq);
  const path out = test::temp_dir("slam_" + std::to_string(getpid())) / "out";
  const test::CliResult r =
      test::run("slam --quiet --kitti " + seq.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"poses_history_file.txt", "pts_history_file.txt", "trajectory.txt",
                        "vo.json", "poses_closed.txt", "trajectory_closed.txt", "loops.csv",
                        "metrics.json", "trajectory.svg", "map.db"}) {
    EXPECT_TRUE(test::fs::exists(out / f)) << f;
  }
  // 51 frames driving straight: no revisit, so no loop, and the keyframes keep their poses.
  const nlohmann::json m = nlohmann::json::parse(test::file_bytes(out / "metrics.json"));
  EXPECT_EQ(m["loops"]["accepted"].get<int>(), 0);
  EXPECT_NEAR(m["ate_after_m"].get<double>(), m["ate_before_m"].get<double>(), 1e-6);
  EXPECT_LT(m["ate_after_m"].get<double>(), 0.2);
  EXPECT_EQ(io::read_sodso_poses((out / "poses_closed.txt").string()).size(),
            io::read_sodso_poses((out / "poses_history_file.txt").string()).size());
}

}  // namespace
}  // namespace loopscan
