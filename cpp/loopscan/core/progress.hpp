#pragma once
// How long-running library calls report how far they are: a callback with (done, total), called
// on the caller's thread only (never concurrently), at most once per item. The library prints
// nothing; the CLI draws a bar or lines from it.
#include <algorithm>
#include <cstddef>
#include <functional>

namespace loopscan {

using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

// Nothing to report for no work (total 0).
inline void report_progress(const ProgressFn& progress, std::size_t done, std::size_t total) {
  if (progress && total > 0) progress(done, total);
}

// From worker `thread` of run_on_threads, `done` counted as that worker's items times the
// thread count: thread 0 (the caller's) reports for all, held one short of `total` since the
// others may still be working; report_progress(total, total) after the join ends it.
inline void report_worker_progress(const ProgressFn& progress, int thread, std::size_t done,
                                   std::size_t total) {
  if (thread == 0 && total > 0) report_progress(progress, std::min(done, total - 1), total);
}

}  // namespace loopscan
