// SIGKILL at any moment of any writing command: the output is the complete old set or the
// complete new set, never a mix, and the next run clears what the killed one left. Each
// command alternates between two parameter sets A and B over one target, killed just before
// and just after the rename that commits its set (both outcomes must occur), then at random
// times within its run. LOOPSCAN_KILLS sets the kills per command (default 6; the campaign in
// scripts/kill-campaign runs 100, and 20 of the half-minute demo).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <map>
#include <random>
#include <thread>

#include "cli/cli_support.hpp"

extern char** environ;

namespace loopscan {
namespace {

using namespace loopscan::test;
using Snapshot = std::map<std::string, std::string>;  // relative path -> bytes ("" if volatile)

// Files holding timings (their bytes differ from run to run): compared by presence only.
bool is_volatile(const fs::path& p) {
  const std::string n = p.filename().string();
  return n == "timing.json" || n == "metrics.json" || n == "vo.json" || n == "summary.json" ||
         n == "report.html" || n == "index.html";
}

Snapshot snapshot(const fs::path& target) {
  Snapshot s;
  if (fs::is_regular_file(target)) {
    s[""] = file_bytes(target);
    return s;
  }
  if (!fs::exists(target)) return s;
  for (const auto& e : fs::recursive_directory_iterator(target)) {
    if (!e.is_regular_file()) continue;
    s[fs::relative(e.path(), target).string()] = is_volatile(e.path()) ? "" : file_bytes(e.path());
  }
  return s;
}

// Starts the CLI with `args` (output discarded), `extra_env` ("NAME=value") added to the
// environment where given, and returns its pid.
pid_t spawn(const std::vector<std::string>& args, const std::string& extra_env = "") {
  std::vector<std::string> all = {LOOPSCAN_CLI};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  std::vector<char*> env;
  for (char** e = environ; *e; ++e) env.push_back(*e);
  std::string extra = extra_env;
  if (!extra.empty()) env.push_back(extra.data());
  env.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data()), 0);
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

int wait_for(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

struct Writer {
  std::string name;
  std::vector<std::string> a, b;  // the command without --out
  fs::path target;
};

struct KillStats {
  int kills = 0, old_set = 0, new_set = 0, mixed = 0;
};

// Runs the A/B alternation: first two kills where the outcome is decided (the writer stopped
// by the io library's test hook just before, then just after, the rename that makes its new
// set visible: the old set, then the new one, must be what they leave), then `kills` SIGKILLs
// at random times; every state seen must be A or B exactly.
KillStats kill_test(const Writer& w, int kills, std::mt19937& rng) {
  auto with_out = [&](std::vector<std::string> args) {
    args.push_back("--out");
    args.push_back(w.target.string());
    return args;
  };
  auto complete = [&](const std::vector<std::string>& args) {
    const auto t0 = std::chrono::steady_clock::now();
    const int status = wait_for(spawn(with_out(args)));
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << w.name;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const double seconds_b = complete(w.b);
  const Snapshot b = snapshot(w.target);
  const double seconds_a = complete(w.a);
  const Snapshot a = snapshot(w.target);
  EXPECT_NE(a, b) << w.name << ": A and B must differ to tell the sets apart";
  KillStats stats;
  for (const char* when : {"before", "after"}) {
    const pid_t pid = spawn(with_out(w.b),
                            std::string("LOOPSCAN_TEST_STOP_AT=") + when + ":" + w.target.string());
    int status = 0;
    waitpid(pid, &status, WUNTRACED);
    if (!WIFSTOPPED(status)) {  // ended, and reaped: its pid is no longer ours to kill
      ADD_FAILURE() << w.name << ": did not stop " << when << " its rename";
      continue;
    }
    kill(pid, SIGKILL);
    wait_for(pid);
    const Snapshot now = snapshot(w.target);
    const bool before = std::string(when) == "before";
    EXPECT_EQ(now, before ? a : b) << w.name << ": killed " << when << " the rename";
    ++stats.kills;
    stats.old_set += now == a;
    stats.new_set += now == b;
    stats.mixed += now != a && now != b;
  }
  if (snapshot(w.target) != b) complete(w.b);
  bool holds_a = false;
  for (int k = 0; k < kills; ++k) {
    const double duration = holds_a ? seconds_b : seconds_a;
    // Every other kill lands near the end, where the set is swapped in.
    std::uniform_real_distribution<double> when(k % 2 ? 0.8 * duration : 0.0, 1.1 * duration);
    const pid_t pid = spawn(with_out(holds_a ? w.b : w.a));
    std::this_thread::sleep_for(std::chrono::duration<double>(when(rng)));
    kill(pid, SIGKILL);
    wait_for(pid);
    const Snapshot now = snapshot(w.target);
    const bool is_a = now == a, is_b = now == b;
    EXPECT_TRUE(is_a || is_b) << w.name << ": kill " << k << " left a set that is neither A nor B ("
                              << now.size() << " files)";
    ++stats.kills;
    stats.old_set += (holds_a ? is_a : is_b);
    stats.new_set += (holds_a ? is_b : is_a);
    stats.mixed += !is_a && !is_b;
    if (!is_a && !is_b) complete(w.a);  // back to a known state
    holds_a = !is_b;
  }
  EXPECT_GT(stats.old_set, 0) << w.name << ": no kill left the old set";
  EXPECT_GT(stats.new_set, 0) << w.name << ": no kill left the new set";
  complete(w.a);  // the next run clears every leftover of the killed ones
  for (const auto& e : fs::directory_iterator(w.target.parent_path())) {
    const std::string n = e.path().filename().string();
    EXPECT_TRUE(n.find(".staging.") == std::string::npos && n.find(".old.") == std::string::npos &&
                n.find(".lock") == std::string::npos && n.find(".tmp.") == std::string::npos)
        << w.name << ": leftover " << n;
  }
  return stats;
}

TEST(CliKill, KilledWritersLeaveTheOldSetOrTheNewOneNeverAMix) {
  const char* env = std::getenv("LOOPSCAN_KILLS");
  const int kills = env ? std::atoi(env) : 6;
  const fs::path d = temp_dir("kill");
  const std::string s = d.string();
  // Inputs: a simulated drive, its signatures, a few rendered frames.
  const std::string poses = s + "/sim/poses_history_file.txt",
                    pts = s + "/sim/pts_history_file.txt";
  write(d / "r30.yaml", "imitation:\n  range_m: 30\n");
  write(d / "seg5.yaml", "odometry_metrics:\n  segment_lengths_m: [5]\n");
  write(d / "voc4.yaml", "baselines:\n  vocabulary:\n    branching: 4\n    depth: 2\n");
  write(d / "voc3.yaml", "baselines:\n  vocabulary:\n    branching: 3\n    depth: 2\n");
  const std::string r30 = s + "/r30.yaml", seg5 = s + "/seg5.yaml";
  for (const std::string& args :
       {"simulate --trajectory builtin:short --seed 3 --out " + s + "/sim",
        "describe --method sc --poses " + poses + " --points " + pts + " --out " + s + "/sc",
        "describe --method sc --config " + r30 + " --poses " + poses + " --points " + pts +
            " --out " + s + "/sc30",
        "render --trajectory builtin:short --frames 24 --scale 0.25 --out " + s + "/ren"}) {
    ASSERT_EQ(run(args).code, 0) << args;
  }
  write(d / "pairs_a.txt", "0.9 1\n0.8 0\n0.7 1\n0.1 0\n");
  write(d / "pairs_b.txt", "0.9 0\n0.8 1\n0.2 1\n");
  const std::string gt = s + "/sim/gt.txt";
  std::vector<Writer> writers = {
      {"describe",
       {"describe", "--method", "sc", "--poses", poses, "--points", pts},
       {"describe", "--method", "sc", "--config", r30, "--poses", poses, "--points", pts},
       d / "w/describe"},
      {"evaluate",
       {"evaluate", "--signatures", s + "/sc", "--gt", gt},
       {"evaluate", "--signatures", s + "/sc30", "--gt", gt},
       d / "w/evaluate"},
      {"pairs",
       {"pairs", "--scores", s + "/pairs_a.txt"},
       {"pairs", "--scores", s + "/pairs_b.txt"},
       d / "w/pairs"},
      {"simulate",
       {"simulate", "--trajectory", "builtin:short", "--seed", "1"},
       {"simulate", "--trajectory", "builtin:short", "--seed", "2"},
       d / "w/simulate"},
      {"render",
       {"render", "--trajectory", "builtin:short", "--frames", "6", "--scale", "0.25"},
       {"render", "--trajectory", "builtin:short", "--frames", "5", "--scale", "0.25", "--season",
        "winter"},
       d / "w/render"},
      {"vo",
       {"vo", "--kitti", s + "/ren", "--config", seg5, "--quiet"},
       {"vo", "--kitti", s + "/ren", "--frames", "18", "--config", seg5, "--quiet"},
       d / "w/vo"},
      {"db build",
       {"db", "build", "--signatures", s + "/sc"},
       {"db", "build", "--signatures", s + "/sc30"},
       d / "w/map.db"},
      {"db query",
       {"db", "query", "--db", s + "/w/map.db", "--signatures", s + "/sc", "--k", "3"},
       {"db", "query", "--db", s + "/w/map.db", "--signatures", s + "/sc", "--k", "5"},
       d / "w/query"},
      {"vocab train",
       {"vocab", "train", "--kitti", s + "/ren", "--config", s + "/voc4.yaml", "--step", "4"},
       {"vocab", "train", "--kitti", s + "/ren", "--config", s + "/voc3.yaml", "--step", "4"},
       d / "w/voc.bin"},
      {"run",
       {"run", "--kitti", s + "/ren", "--methods", "sc", "--config", seg5, "--quiet"},
       {"run", "--kitti", s + "/ren", "--methods", "delight", "--config", seg5, "--quiet"},
       d / "w/run"},
  };
  if (kills >= 50) {
    writers.push_back({"demo", {"demo", "--seed", "7"}, {"demo", "--seed", "8"}, d / "w/demo"});
  }
  std::mt19937 rng(2026);
  for (const Writer& w : writers) {
    // The demo runs for half a minute: a fifth of the kills (at least 10) keeps the campaign short.
    const int n = w.name == "demo" ? std::max(10, kills / 5) : kills;
    const KillStats st = kill_test(w, n, rng);
    std::printf("%-12s %3d kills: %3d left the old set, %3d the new set, %d mixed\n",
                w.name.c_str(), st.kills, st.old_set, st.new_set, st.mixed);
  }
  fs::remove_all(d);
}

}  // namespace
}  // namespace loopscan
