#pragma once
// How long-running library calls report how far they are: a callback with (done, total), called
// on the caller's thread only (never concurrently), at most once per item. The library prints
// nothing; the CLI draws a bar or lines from it.
#include <cstddef>
#include <functional>

namespace loopscan {

using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

inline void report_progress(const ProgressFn& progress, std::size_t done, std::size_t total) {
  if (progress) progress(done, total);
}

}  // namespace loopscan
