#pragma once
// Progress of one CLI step on stderr: on a terminal a bar redrawn in place with the rate and the
// remaining time; otherwise a plain line every 10 % (only when the step takes over a second).
// finish() always prints one summary line with the step's own time.
#include <chrono>
#include <cstddef>
#include <string>

#include "loopscan/core/progress.hpp"

namespace loopscan::cli {

class StepProgress {
 public:
  // `unit`: what is counted ("keyframes", "queries"); quiet = print nothing at all.
  StepProgress(std::string label, std::string unit, bool quiet = false);
  // A step left by an exception ends its drawn bar, so the error starts on a line of its own.
  ~StepProgress();
  StepProgress(const StepProgress&) = delete;
  StepProgress& operator=(const StepProgress&) = delete;
  void update(std::size_t done, std::size_t total);
  // "<label>: <done> <unit> in <s> s (<rate>/s)<extra>", ending a drawn bar first.
  void finish(const std::string& extra = "");
  double seconds() const;
  ProgressFn callback() {
    return [this](std::size_t done, std::size_t total) { update(done, total); };
  }

 private:
  std::string label_, unit_;
  bool quiet_, terminal_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::size_t done_ = 0, total_ = 0;
  int last_decile_ = 0;
  bool drawn_ = false, finished_ = false;
};

// "[k/N] what" on stdout, k counting up from 1: each step of a command numbered once.
class StepCounter {
 public:
  explicit StepCounter(int steps) : steps_(steps) {}
  void next(const std::string& what);

 private:
  int steps_, done_ = 0;
};

// Runs work() with `slot` (an options struct's progress callback) drawing one part of a step,
// then ends it: the summary line, and the slot emptied so it never outlives the bar.
template <typename Work>
auto with_progress(const std::string& label, const std::string& unit, bool quiet, ProgressFn& slot,
                   Work&& work) {
  StepProgress bar(label, unit, quiet);
  slot = bar.callback();
  struct Clear {
    ProgressFn& slot;
    ~Clear() { slot = {}; }
  } clear{slot};
  auto result = work();
  bar.finish();
  return result;
}

// "12 s", "3 min 05 s": for remaining times and step times.
std::string format_duration(double seconds);

}  // namespace loopscan::cli
