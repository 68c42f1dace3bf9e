// loopscan_fuzz: a seeded mutation fuzzer for every reader. Each case mutates a valid input,
// writes it to a scratch directory and reads it back in-process. A reader may accept the
// input or reject it with io::InputError / std::invalid_argument (the CLI's exit code 2);
// anything else is a finding: another exception (exit code 1 on the CLI), a hang, or a crash
// (with a sanitizer build: any memory error or undefined behaviour). A crash leaves its input
// in the scratch directory, whose path is printed first; other findings are copied to
// --findings. Deterministic: case i of a target depends only on --seed, the name and i.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "fuzz_target.hpp"
#include "loopscan/io/errors.hpp"
#include "mutate.hpp"
#include "run_case.hpp"

#if defined(__SANITIZE_ADDRESS__)
// Allocations beyond 3 GB fail (std::bad_alloc, a finding) instead of exhausting the machine.
extern "C" const char* __asan_default_options() {
  return "allocator_may_return_null=1:max_allocation_size_mb=3072";
}
#endif

extern char** environ;

namespace loopscan::fuzz {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  double seconds = 0;  // total budget, split evenly over the targets
  long cases = 1000;   // per target, when no time budget is given
  std::string only;    // substring of the target names
  unsigned long seed = 1;
  std::string findings = "fuzz-findings";
  double hang_seconds = 20;
  bool self_test = false;  // fuzz a deliberately faulty reader: succeed only if it is caught
  std::string cli;         // --cli PATH: run the `loopscan` commands instead of the readers
};

// A reader with a planted defect (it throws std::runtime_error on a NaN token, as a reader
// that forgot to report bad input would), for --self-test.
Target faulty_reader() {
  return single_file("self-test:faulty", "numbers.txt", Format::Text, {"1 2 3\n4 5 6\n"},
                     [](const std::string& path) {
                       std::ifstream in(path);
                       const std::string text{std::istreambuf_iterator<char>(in), {}};
                       if (text.find("nan") != std::string::npos) {
                         throw std::runtime_error("planted defect");
                       }
                     });
}

struct Counts {
  long cases = 0, accepted = 0, clean = 0, findings = 0;
  double seconds = 0;
};

std::uint64_t case_seed(const Options& o, const std::string& name, long i) {
  return std::hash<std::string>{}(name) ^ (o.seed * 0x9E3779B97F4A7C15ULL) ^
         (static_cast<std::uint64_t>(i) * 0xC2B2AE3D27D4EB4FULL);
}

void write_files(const fs::path& dir, const Files& files) {
  fs::remove_all(dir);
  for (const auto& [name, bytes] : files) {
    fs::create_directories((dir / name).parent_path());
    std::ofstream(dir / name, std::ios::binary) << bytes;
  }
}

// What the watchdog reads while a case runs (atomics: it is another thread).
struct Progress {
  std::atomic<long> started_ms{0};  // 0: no case running
  std::atomic<long> target{0}, index{0};
};

Counts fuzz_target(const Target& t, const Options& o, const fs::path& work, double budget,
                   Progress& progress) {
  Counts c;
  const auto t0 = Clock::now();
  const fs::path dir = work / "case";
  for (long i = 0;; ++i) {
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
    if (budget > 0 ? elapsed >= budget : i >= o.cases) break;
    std::mt19937_64 rng(case_seed(o, t.name, i));
    Files files = t.seeds[rng() % t.seeds.size()];
    std::string& victim = t.mutated_file.empty() ? files.begin()->second : files.at(t.mutated_file);
    victim = mutate(victim, t, rng);
    write_files(dir, files);
    progress.index = i;
    progress.started_ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch())
            .count();
    std::string what;
    const int outcome = o.cli.empty()
                            ? run_reader(t, dir, what)
                            : run_command(o.cli, o.hang_seconds, t, dir, work / "out", i, what);
    progress.started_ms = 0;
    ++c.cases;
    c.accepted += outcome == 0;
    c.clean += outcome == 1;
    if (outcome == 2) {
      ++c.findings;
      const fs::path keep = fs::path(o.findings) / (t.name + "-" + std::to_string(i));
      write_files(keep, files);
      std::printf("FINDING %s case %ld: %s (input kept in %s)\n", t.name.c_str(), i, what.c_str(),
                  keep.c_str());
    }
  }
  c.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return c;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--seconds")
      o.seconds = std::stod(value());
    else if (a == "--cases")
      o.cases = std::stol(value());
    else if (a == "--target")
      o.only = value();
    else if (a == "--seed")
      o.seed = std::stoul(value());
    else if (a == "--findings")
      o.findings = value();
    else if (a == "--hang-seconds")
      o.hang_seconds = std::stod(value());
    else if (a == "--self-test")
      o.self_test = true;
    else if (a == "--cli")
      o.cli = value();
    else
      throw std::invalid_argument("unknown option " + a +
                                  " (--seconds S | --cases N, --target NAME, --seed K, "
                                  "--findings DIR, --hang-seconds S, --self-test, --cli PATH)");
  }
  return o;
}

int main_impl(int argc, char** argv) {
  const Options o = parse(argc, argv);
#if !defined(__SANITIZE_ADDRESS__)
  const rlimit memory{rlim_t{4} << 30, rlim_t{4} << 30};  // 4 GB: runaway allocations throw
  setrlimit(RLIMIT_AS, &memory);
#endif
  std::vector<Target> targets;
  if (o.self_test) {
    targets.push_back(faulty_reader());
  } else if (!o.cli.empty()) {
    targets = cli_targets();
  } else {
    targets = text_targets();
    for (Target& t : binary_targets()) targets.push_back(std::move(t));
  }
  std::vector<const Target*> chosen;
  for (const Target& t : targets) {
    if (t.name.find(o.only) != std::string::npos) chosen.push_back(&t);
  }
  if (chosen.empty()) throw std::invalid_argument("no target matches '" + o.only + "'");
  const fs::path work = fs::temp_directory_path() / ("loopscan_fuzz_" + std::to_string(::getpid()));
  std::printf(
      "fuzzing %zu readers; a crash leaves its input in %s/case (the JPEG decoder's\n"
      "messages in %s/decoder-stderr.txt)\n",
      chosen.size(), work.c_str(), work.c_str());
  std::fflush(stdout);

  Progress progress;
  std::atomic<bool> done{false};
  std::thread watchdog([&] {  // a case running longer than --hang-seconds is a finding
    while (!done) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      const long s = progress.started_ms;
      const long now =
          std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch())
              .count();
      if (s != 0 && now - s > static_cast<long>(1000 * o.hang_seconds)) {
        std::printf("FINDING hang: %s case %ld ran %.0f s (input in %s/case)\n",
                    chosen[static_cast<std::size_t>(progress.target)]->name.c_str(),
                    static_cast<long>(progress.index), (now - s) / 1000.0, work.c_str());
        std::_Exit(3);
      }
    }
  });
  std::printf("| reader | cases | accepted | clean errors | findings | ms per case |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  long findings = 0;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Target* t = chosen[k];
    progress.target = static_cast<long>(k);
    const double budget = o.seconds > 0 ? o.seconds / static_cast<double>(chosen.size()) : 0;
    const Counts c = fuzz_target(*t, o, work, budget, progress);
    findings += c.findings;
    std::printf("| %s | %ld | %ld | %ld | %ld | %.2f |\n", t->name.c_str(), c.cases, c.accepted,
                c.clean, c.findings, c.cases ? 1000 * c.seconds / c.cases : 0.0);
    std::fflush(stdout);
  }
  done = true;
  watchdog.join();
  fs::remove_all(work);
  std::printf("%ld findings\n", findings);
  if (o.self_test) return findings > 0 ? 0 : 1;  // the planted defect must be found
  return findings == 0 ? 0 : 1;
}

}  // namespace
}  // namespace loopscan::fuzz

int main(int argc, char** argv) {
  try {
    return loopscan::fuzz::main_impl(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loopscan_fuzz: %s\n", e.what());
    return 2;
  }
}
