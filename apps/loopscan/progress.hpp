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
  bool drawn_ = false;
};

// "12 s", "3 min 05 s": for remaining times and step times.
std::string format_duration(double seconds);

}  // namespace loopscan::cli
