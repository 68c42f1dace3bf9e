// The CLI under hostile input: option values, files that imply unbounded time or memory,
// values that parse but make no sense, and output directories shared or not ours. Every case
// must end quickly with exit code 2 and a message naming the culprit, writing nothing.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cli/cli_support.hpp"
#include "loopscan/io/output_set.hpp"
#include "support/png_encoder.hpp"

namespace loopscan {
namespace {

using namespace loopscan::test;

bool has(const CliResult& r, const std::string& part) {
  return r.output.find(part) != std::string::npos;
}

std::string describe_args(const fs::path& d) {
  return "describe --method sc --poses " + (d / "poses.txt").string() + " --points " +
         (d / "pts.txt").string();
}

TEST(CliHardening, OptionValuesOutsideTheirRangeAreRefused) {
  const fs::path d = temp_dir("options");
  write_sequence(d, 40);
  const std::string out = " --out " + (d / "o").string();
  for (const std::string bad :
       {" --threads 200000000", " --threads 0", " --threads inf", " --threads 1e308",
        " --threads nan", " --threads -5", " --threads x"}) {
    const CliResult r = run(describe_args(d) + bad + out);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.output;
    EXPECT_TRUE(has(r, bad.substr(1, bad.find(' ', 1) - 1))) << r.output;  // names the option
  }
  // Checked before any file is opened: the message names the option (the files do not exist).
  for (const auto& [args, option] : std::vector<std::pair<std::string, std::string>>{
           {"db query --db x --signatures y --k 0", "--k"},
           {"db query --db x --signatures y --sessions nan", "--sessions"},
           {"vocab train --kitti x --step 0", "--step"},
           {"render --trajectory builtin:short --scale 0", "--scale"},
           {"simulate --trajectory builtin:short --resets -3", "--resets"}}) {
    const CliResult r = run(args + " --out " + (d / "q").string());
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(has(r, option + ": expected a finite number in [")) << r.output;
  }
  EXPECT_FALSE(fs::exists(d / "o") || fs::exists(d / "q"));
  // The configuration's values are checked as strictly, naming the file, line and key.
  for (const std::string value : {"inf", "1e308", "nan", "-5"}) {
    const CliResult r =
        run(describe_args(d) + config(d, "range", "imitation:\n  range_m: " + value + "\n") + out);
    EXPECT_EQ(r.code, 2) << value << ": " << r.output;
    EXPECT_TRUE(has(r, "range.yaml:2: expected a number in [0.1, 1000] for imitation.range_m"))
        << r.output;
  }
  // In range: the same run works and describes on many threads identically.
  ASSERT_EQ(run(describe_args(d) + " --threads 3" + out).code, 0);
}

TEST(CliHardening, UnboundedInputsEndInAClearErrorFast) {
  const fs::path d = temp_dir("unbounded");
  write_sequence(d, 40);
  const auto t0 = std::chrono::steady_clock::now();
  // A KITTI sequence whose images announce 65535 x 65535 pixels.
  fs::create_directories(d / "seq/image_0");
  fs::create_directories(d / "seq/image_1");
  write(d / "seq/calib.txt",
        "P0: 700 0 600 0 0 700 180 0 0 0 1 0\nP1: 700 0 600 -380 0 700 180 0 0 0 1 0\n");
  write(d / "seq/times.txt", "0\n0.1\n");
  for (const char* f :
       {"image_0/000000.png", "image_0/000001.png", "image_1/000000.png", "image_1/000001.png"}) {
    std::ofstream(d / "seq" / f, std::ios::binary) << png_announcing(65535, 65535);
  }
  // An endless line (like /dev/zero): the text reader stops at its line bound.
  CliResult r = run("describe --method sc --poses " + (d / "poses.txt").string() +
                    " --points /dev/zero --out " + (d / "o").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "/dev/zero:1: expected lines of at most 4 MiB")) << r.output;
  write(d / "kf/incoming_id_file.txt", "0\n");
  r = run("describe --method bow --kitti " + (d / "seq").string() + " --keyframes " +
          (d / "kf").string() + " --vocab /dev/zero --out " + (d / "b").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "/dev/zero:1: expected lines")) << r.output;
  // A trajectory with one 1000 km jump: no world is built for it.
  std::ofstream jump(d / "jump.txt");
  for (int i = 0; i < 30; ++i) jump << "1 0 0 0 0 1 0 0 0 0 1 " << (i == 10 ? 1e6 : i) << "\n";
  jump.close();
  r = run("simulate --trajectory kitti:" + (d / "jump.txt").string() + " --out " +
          (d / "s").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "jump.txt: expected a route of at most 100 km")) << r.output;
  EXPECT_TRUE(has(r, "between frames 9 and 10")) << r.output;
  r = run("vo --kitti " + (d / "seq").string() + " --quiet --out " + (d / "vo").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "000000.png: expected an image of 1..32768 px a side")) << r.output;
  EXPECT_FALSE(has(r, "libpng")) << r.output;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 60.0);  // generous: a sanitizer build; unbounded inputs used to take minutes
}

TEST(CliHardening, ValuesThatParseButMakeNoSenseAreRefused) {
  const fs::path d = temp_dir("values");
  write_sequence(d, 40);
  ASSERT_EQ(run(describe_args(d) + " --out " + (d / "sc").string()).code, 0);
  // frames.txt must hold rotations, signatures finite numbers.
  const std::vector<std::string> frames = read_lines(d / "sc/frames.txt");
  CliResult r;
  for (const char* frame : {"nan 0 0 0 1 0 0 0 1", "2 0 0 0 1 0 0 0 1", "1 0 0 0 1 0 0 0 0"}) {
    std::string text = std::string(frame) + "\n";
    for (std::size_t i = 1; i < frames.size(); ++i) text += frames[i] + "\n";
    write(d / "sc/frames.txt", text);
    r = run("evaluate --method sc --signatures " + (d / "sc").string() + " --gt " +
            (d / "poses.txt").string() + " --out " + (d / "e").string());
    EXPECT_EQ(r.code, 2) << frame;
    EXPECT_TRUE(has(r, "frames.txt:1: expected")) << r.output;
  }
  // Labels of `pairs` are 0 or 1; the error names the format.
  for (const char* label : {"nan", "2", "0.5", "1e308"}) {
    write(d / "pairs.txt", std::string("0.9 1\n0.4 ") + label + "\n");
    r = run("pairs --scores " + (d / "pairs.txt").string() + " --out " + (d / "p").string());
    EXPECT_EQ(r.code, 2) << label;
    EXPECT_TRUE(has(r, "pairs.txt:2: expected `score label`")) << r.output;
  }
  // A camera yaml with a bad value: exit 2 (it was 1), with file and line.
  write(d / "cam.yaml",
        "Camera.fx: 700\nCamera.fy: 700\nCamera.cx: 600\nCamera.cy: 180\n"
        "Camera.width: 1241\nCamera.height: 376\nCamera.bf: -1\n");
  r = run("render --trajectory builtin:short --frames 1 --calib " + (d / "cam.yaml").string() +
          " --out " + (d / "r").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "cam.yaml:7: expected Camera.bf")) << r.output;
  EXPECT_FALSE(fs::exists(d / "e") || fs::exists(d / "p") || fs::exists(d / "r"));
}

TEST(CliHardening, OutputDirectoriesAreOursAloneAndNeverHoldTheInputs) {
  const fs::path d = temp_dir("outputs");
  write_sequence(d, 40);
  // A directory with someone else's files is not replaced.
  write(d / "mine/notes.txt", "keep");
  CliResult r = run(describe_args(d) + " --out " + (d / "mine").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "no .loopscan marker")) << r.output;
  EXPECT_EQ(file_bytes(d / "mine/notes.txt"), "keep");
  // Inputs inside the output directory would be replaced with it: refused.
  ASSERT_EQ(run(describe_args(d) + " --out " + (d / "sc").string()).code, 0);
  r = run("evaluate --method sc --signatures " + (d / "sc").string() + " --gt " +
          (d / "poses.txt").string() + " --out " + (d / "sc").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "lies inside the output directory")) << r.output;
  EXPECT_TRUE(fs::exists(d / "sc/signatures.txt"));
  // A second command on the same output is refused while the first holds it.
  {
    io::OutputSet busy((d / "sc").string(), io::OutputSet::Kind::Directory);
    r = run(describe_args(d) + " --out " + (d / "sc").string());
    EXPECT_EQ(r.code, 2);
    EXPECT_TRUE(has(r, "no other loopscan command writing it")) << r.output;
  }
  // Re-running over a loopscan output replaces it as a whole.
  ASSERT_EQ(run(describe_args(d) + " --threads 2 --out " + (d / "sc").string()).code, 0);
  EXPECT_NE(file_bytes(d / "sc/.loopscan").find("--threads 2"), std::string::npos);
  EXPECT_FALSE(has_temp_files(d));
}

}  // namespace
// `plot`: one <path> per --y column; a wrong column, a bad cell or a missing header names the
// file, line and what was expected, and leaves no file.
TEST(Cli, PlotDrawsCsvColumnsAndRejectsBadTables) {
  const fs::path d = temp_dir("plot");
  write(d / "sweep.csv", "offset,same,opposite\n-1,0.2,0.7\n0,0.8,\n1,0.3,0.1\n");
  CliResult r = run("plot --csv " + (d / "sweep.csv").string() +
                    " --x offset --y same,opposite --names 'S, left' O --y-range 0 1 --out " +
                    (d / "f.svg").string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(d / "f.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t paths = 0;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1))
    ++paths;
  EXPECT_GE(paths, 2u);  // the two series (frame and grid may add more)
  EXPECT_NE(svg.find(">S, left<"), std::string::npos);  // legend text keeps its comma
  EXPECT_NE(svg.find(">O<"), std::string::npos);
  r = run("plot --csv " + (d / "sweep.csv").string() + " --x offset --y sam --out " +
          (d / "g.svg").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r,
                  "sweep.csv:1: expected a column named 'sam' (columns: offset, same, "
                  "opposite)"))
      << r.output;
  write(d / "bad.csv", "a,b\n1,2\n3,x\n");
  r = run("plot --csv " + (d / "bad.csv").string() + " --x a --y b --out " +
          (d / "g.svg").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "bad.csv:3: expected a finite number or an empty cell in column 'b'"))
      << r.output;
  write(d / "short.csv", "a,b\n1\n");
  r = run("plot --csv " + (d / "short.csv").string() + " --x a --y b --out " +
          (d / "g.svg").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r, "short.csv:2: expected 2 comma-separated cells")) << r.output;
  r = run("plot --csv " + (d / "sweep.csv").string() + " --x offset --y same --names A B --out " +
          (d / "g.svg").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(fs::exists(d / "g.svg"));
}

// Guidance: --version, the closest subcommand or option for a misspelling, comma lists.
TEST(Cli, VersionSuggestionsAndCommaLists) {
  CliResult r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(has(r, "loopscan 0.")) << r.output;
  const std::pair<const char*, const char*> mistakes[] = {
      {"describ --method sc", "unknown command 'describ' (did you mean 'describe'?)"},
      {"describe --methdo sc --out x", "unknown option --methdo (did you mean --method?)"},
      {"evaluate --method sc --signatures a --gt b --out c --fusoin fused",
       "did you mean --fusion?"},
      {"evaluate --method gits --signatures a --gt b --out c",
       "(expected sc, m2dp, delight, bev, gist or bow; did you mean 'gist'?)"},
      {"frobnicate", "unknown command 'frobnicate'; commands: describe"}};
  for (const auto& [line, message] : mistakes) {
    r = run(line);
    EXPECT_EQ(r.code, 2) << line;
    EXPECT_TRUE(has(r, message)) << line << ": " << r.output;
  }
  const fs::path d = temp_dir("comma");
  write(d / "t.csv", "x,a,b\n0,1,2\n1,2,3\n");
  r = run("plot --csv " + (d / "t.csv").string() + " --x x --y a,b --out " +
          (d / "f.svg").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r, "2 series")) << r.output;
}

// Every option of every command says what it is: in `--help`, each option line is followed by
// its description, on the same line or the next (CLI11 wraps long types).
TEST(Cli, EveryOptionHasHelpText) {
  std::vector<std::string> commands;
  std::istringstream top(run("--help").output);
  bool in_list = false;
  for (std::string line; std::getline(top, line);) {
    if (line.rfind("Subcommands:", 0) == 0)
      in_list = true;
    else if (in_list && line.size() > 2 && line[0] == ' ' && line[2] != ' ')
      commands.push_back(line.substr(2, line.find(' ', 2) - 2));
  }
  ASSERT_GE(commands.size(), 12u);
  for (const std::string nested : {"db build", "db query", "vocab train"})
    commands.push_back(nested);
  std::size_t options = 0;
  for (const std::string& command : commands) {
    const CliResult r = run(command + " --help");
    ASSERT_EQ(r.code, 0) << command;
    std::vector<std::string> lines;
    std::istringstream in(r.output);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::string& l = lines[i];
      if (l.rfind("  -", 0) != 0) continue;
      ++options;
      // "  --name TYPE=default   description": text after a run of 2+ spaces past column 2.
      const std::size_t gap = l.find("  ", 3);
      const bool same_line =
          gap != std::string::npos && l.find_first_not_of(' ', gap) != std::string::npos;
      const bool next_line = i + 1 < lines.size() && lines[i + 1].rfind("        ", 0) == 0 &&
                             lines[i + 1].find_first_not_of(' ') != std::string::npos;
      EXPECT_TRUE(same_line || next_line) << command << ": " << l;
    }
  }
  EXPECT_GE(options, 100u);
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

}  // namespace loopscan
