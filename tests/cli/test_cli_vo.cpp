// The `loopscan` CLI: vo and run on rendered images, the image baselines.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "loopscan/config/configuration.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/io/png.hpp"
#include "loopscan/io/vo_files.hpp"
#include "loopscan/vo/run_sequence.hpp"

#include "cli/cli_support.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

TEST(Cli, VoAndRunFromRenderedImages) {
  const fs::path d = temp_dir("vo");
  const std::string seq = (d / "seq").string();
  ASSERT_EQ(run("render --trajectory builtin:short --scale 0.25 --frames 36 --out " + seq).code, 0);
  const std::string segments =
      config(d, "segments", "odometry_metrics:\n  segment_lengths_m: [10, 20]\n");
  const CliResult vo =
      run("vo --kitti " + seq + " --out " + (d / "vo").string() + segments + " --quiet");
  ASSERT_EQ(vo.code, 0) << vo.output;
  EXPECT_NE(vo.output.find("fps"), std::string::npos) << vo.output;
  EXPECT_NE(vo.output.find("translation"), std::string::npos) << vo.output;
  for (const char* f :
       {"poses_history_file.txt", "pts_history_file.txt", "trajectory.txt", "vo.json"})
    EXPECT_TRUE(fs::exists(d / "vo" / f)) << f;
  std::ifstream json_in(d / "vo/vo.json");
  const nlohmann::json j = nlohmann::json::parse(json_in);
  EXPECT_EQ(j["frames"].get<int>(), 36);
  EXPECT_GT(j["metrics"]["segments"].get<int>(), 0);
  EXPECT_LT(j["metrics"]["translation_percent"].get<double>(), 5.0);
  EXPECT_GT(j["fps"].get<double>(), 0.0);
  // The CLI's trajectory is the library's (the default configuration's VO on the same frames),
  // written by the same writer: byte for byte. The library's own tests bound its accuracy.
  const vo::SequenceRun library =
      vo::run_stereo_vo(io::open_kitti_sequence(seq), Configuration::defaults().vo, {});
  std::vector<Eigen::Matrix<double, 3, 4>> rows;
  for (const Eigen::Isometry3d& T : library.trajectory) rows.push_back(T.matrix().topRows<3>());
  io::write_kitti_poses((d / "library_trajectory.txt").string(), rows);
  EXPECT_EQ(rows.size(), 36u);
  EXPECT_EQ(file_bytes(d / "vo/trajectory.txt"), file_bytes(d / "library_trajectory.txt"));
  // `describe` reads the VO's SO-DSO history unchanged.
  const CliResult described = run(
      "describe --method sc --poses " + (d / "vo/poses_history_file.txt").string() + " --points " +
      (d / "vo/pts_history_file.txt").string() + " --out " + (d / "sc").string());
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
  const CliResult all =
      run("run --kitti " + seq + " --out " + (d / "run").string() + " --methods sc delight" +
          config(d, "segment10", "odometry_metrics:\n  segment_lengths_m: [10]\n") + " --quiet");
  ASSERT_EQ(all.code, 0) << all.output;
  // --quiet: the numbered steps and the results, no progress or per-part summary lines.
  EXPECT_NE(all.output.find("[2/5] sc: describe"), std::string::npos) << all.output;
  for (const char* chatter : {"close loops:", "  describe:", "  match:", "stereo VO:"})
    EXPECT_EQ(all.output.find(chatter), std::string::npos) << chatter << "\n" << all.output;
  for (const char* f :
       {"report.html", "summary.json", "vo/vo.json", "sc/signatures.txt", "delight/signatures.txt"})
    EXPECT_TRUE(fs::exists(d / "run" / f)) << f;
  std::ifstream summary_in(d / "run/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_in);
  ASSERT_EQ(summary["methods"].size(), 2u);
  for (const nlohmann::json& m : summary["methods"]) {
    // 36 m are too short for the imitation's warm-up plus the 100-keyframe mask: nothing to score.
    EXPECT_EQ(m["evaluated"].get<bool>(), m["places"].get<int>() > 0);
    EXPECT_EQ(fs::exists(d / "run" / m["method"].get<std::string>() / "metrics.json"),
              m["evaluated"].get<bool>());
    if (m["evaluated"].get<bool>()) {  // split by the direction of the revisit
      EXPECT_EQ(m["by_direction"]["same"]["n_loops"].get<int>() +
                    m["by_direction"]["opposite"]["n_loops"].get<int>(),
                m["n_gt_loops"].get<int>());
    }
  }
  EXPECT_FALSE(has_temp_files(d));
  // reproduce.sh: `describe` of the written VO files gives the run's signatures byte for byte.
  const std::string script = (d / "run/reproduce.sh").string(), log = (d / "re.log").string();
  EXPECT_NE(all.output.find("reproduce.sh"), std::string::npos) << all.output;
  EXPECT_EQ(
      std::system(("sh " + script + " " + (d / "re").string() + " >" + log + " 2>&1").c_str()), 0)
      << file_bytes(log);
  EXPECT_NE(file_bytes(script).find("cmp "), std::string::npos);
  EXPECT_FALSE(read_lines(d / "run/sc/signatures.txt").empty());  // cmp compares something
  // Bad input: exit code 2, the file named, nothing written.
  const CliResult missing =
      run("vo --kitti " + (d / "nope").string() + " --out " + (d / "x").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.output.find("nope"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(d / "x"));
  EXPECT_EQ(run("vo --kitti " + seq + config(d, "points0", "vo:\n  points_per_keyframe: 0\n") +
                " --out " + (d / "y").string())
                .code,
            2);
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
  const std::string small = config(d, "small",
                                   "baselines:\n  vocabulary:\n    branching: 4\n    depth: 3\n"
                                   "  orb:\n    features: 500\n");
  const CliResult voc = run("vocab train --kitti " + seq + " --step 3" + small + " --out " +
                            (d / "voc.bin").string());
  ASSERT_EQ(voc.code, 0) << voc.output;
  ASSERT_EQ(run("vocab train --kitti " + seq + " --step 3" + small + " --text --out " +
                (d / "voc.txt").string())
                .code,
            0);
  for (const std::string& m : {std::string("gist"), std::string("bow")}) {
    const std::string vocab = m == "bow" ? " --vocab " + (d / "voc.txt").string() : "";
    const CliResult desc = run("describe --method " + m + " --kitti " + seq + " --keyframes " +
                               (d / "kf").string() + vocab + " --out " + (d / m).string());
    ASSERT_EQ(desc.code, 0) << desc.output;
    EXPECT_EQ(read_lines(d / m / "incoming_id_file.txt").size(), 6u);
    const CliResult ev = run(
        "evaluate --method " + m + " --signatures " + (d / m).string() + " --gt " + seq +
        "/poses.txt" +
        config(d, "protocol", "evaluation:\n  same_session:\n    mask: 3\n    threshold_m: 3\n") +
        " --out " + (d / m / "eval").string());
    ASSERT_EQ(ev.code, 0) << ev.output;
    std::ifstream in(d / m / "eval/metrics.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["n_queries"].get<int>(), 6);
    EXPECT_EQ(j["method"].get<std::string>(), m);
  }
  EXPECT_EQ(read_lines(d / "gist/signatures.txt").size(), 6u);
  // GIST on two threads: the same descriptors.
  ASSERT_EQ(run("describe --method gist --threads 2 --kitti " + seq + " --keyframes " +
                (d / "kf").string() + " --out " + (d / "gist2").string())
                .code,
            0);
  EXPECT_EQ(read_lines(d / "gist2/signatures.txt"), read_lines(d / "gist/signatures.txt"));
  EXPECT_EQ(read_lines(d / "bow/bow.txt").size(), 6u);
  // Bad input: no vocabulary, a keyframe beyond the sequence, a damaged bow.txt.
  EXPECT_EQ(run("describe --method bow --kitti " + seq + " --keyframes " + (d / "kf").string() +
                " --out " + (d / "x").string())
                .code,
            2);
  fs::create_directories(d / "kf2");
  write(d / "kf2/incoming_id_file.txt", "0\n99\n");
  const CliResult beyond = run("describe --method gist --kitti " + seq + " --keyframes " +
                               (d / "kf2").string() + " --out " + (d / "y").string());
  EXPECT_EQ(beyond.code, 2);
  EXPECT_NE(beyond.output.find("99"), std::string::npos) << beyond.output;
  EXPECT_FALSE(fs::exists(d / "y"));
  write(d / "bow/bow.txt", "1 0.5 3 0.5\n4 0.25 2 0.75\n");
  const CliResult bad = run("evaluate --method bow --signatures " + (d / "bow").string() +
                            " --gt " + seq + "/poses.txt --out " + (d / "z").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.output.find("bow.txt:2"), std::string::npos) << bad.output;
  EXPECT_FALSE(has_temp_files(d));
}

}  // namespace
}  // namespace loopscan
