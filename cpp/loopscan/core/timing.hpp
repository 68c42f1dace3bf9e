#pragma once
// Stage timings: milliseconds since a steady-clock time point.
#include <chrono>

namespace loopscan {

using StageClock = std::chrono::steady_clock;

inline double ms_since(StageClock::time_point t0) {
  return std::chrono::duration<double, std::milli>(StageClock::now() - t0).count();
}

}  // namespace loopscan
