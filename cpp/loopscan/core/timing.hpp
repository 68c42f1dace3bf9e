#pragma once
// Stage timings: milliseconds since a steady-clock time point.
#include <chrono>

namespace loopscan {

using StageClock = std::chrono::steady_clock;

inline double ms_since(StageClock::time_point t0) {
  return std::chrono::duration<double, std::milli>(StageClock::now() - t0).count();
}

// Adds the milliseconds its scope lasted to `total_ms` when the scope ends (also by an
// exception): one line per timed stage instead of clock reads around it.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& total_ms) : total_ms_(total_ms), start_(StageClock::now()) {}
  ~ScopedTimer() { total_ms_ += ms_since(start_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& total_ms_;
  StageClock::time_point start_;
};

}  // namespace loopscan
