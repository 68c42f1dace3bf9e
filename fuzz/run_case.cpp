#include "run_case.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <thread>

#include "loopscan/io/errors.hpp"

extern char** environ;

namespace loopscan::fuzz {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

// Sends fd 2 to `file` while alive (libjpeg inside OpenCV warns on stderr about every damaged
// JPEG it still decodes); a crash report written meanwhile stays in that file.
class StderrTo {
 public:
  explicit StderrTo(const fs::path& file) : saved_(::dup(2)) {
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 2);
      ::close(fd);
    }
  }
  ~StderrTo() {
    ::dup2(saved_, 2);
    ::close(saved_);
  }
  StderrTo(const StderrTo&) = delete;
  StderrTo& operator=(const StderrTo&) = delete;

 private:
  int saved_;
};

}  // namespace

int run_command(const std::string& cli, double hang_seconds, const Target& t, const fs::path& dir,
                const fs::path& out, long variant, std::string& what) {
  fs::remove_all(out);
  std::vector<std::string> args = {cli};
  for (std::string& a : t.command(dir.string(), out.string(), variant)) args.push_back(a);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string log = (dir.parent_path() / "cli.txt").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = -1;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) throw std::runtime_error("cannot start " + cli);
  int status = 0;
  const auto t0 = Clock::now();
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(Clock::now() - t0).count() > hang_seconds) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      what = "the command ran longer than " + std::to_string(hang_seconds) + " s";
      return 2;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 2)) {
    return WEXITSTATUS(status) == 0 ? 0 : 1;
  }
  std::ifstream in(log);
  const std::string output{std::istreambuf_iterator<char>(in), {}};
  what = (WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                            : "signal " + std::to_string(WTERMSIG(status))) +
         ": " + output.substr(0, 2000);
  return 2;
}

int run_reader(const Target& t, const fs::path& dir, std::string& what) {
  std::optional<StderrTo> quiet;
  if (t.noisy_stderr) quiet.emplace(dir.parent_path() / "decoder-stderr.txt");
  try {
    t.read(dir.string());
    return 0;
  } catch (const io::InputError&) {
    return 1;
  } catch (const std::invalid_argument&) {
    return 1;
  } catch (const std::exception& e) {
    what = std::string("unexpected exception: ") + e.what();
  } catch (...) {
    what = "unexpected exception of unknown type";
  }
  return 2;
}

}  // namespace loopscan::fuzz
