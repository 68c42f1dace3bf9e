#pragma once
// Runs work(t) for t = 0 .. threads-1, thread 0 on the caller's thread. Each worker takes the
// items i = t, t + threads, ... so the split, and therefore every result, is deterministic.
// An exception leaving a worker is kept, every thread is joined, then the first one (lowest t)
// is rethrown: a throwing item (a bad input, a caller's callback) never ends the process.
#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace loopscan {

template <typename Work>
void run_on_threads(int threads, Work&& work) {
  std::vector<std::exception_ptr> failed(threads > 1 ? static_cast<std::size_t>(threads) : 1);
  const auto guarded = [&work, &failed](int t) {
    try {
      work(t);
    } catch (...) {
      failed[static_cast<std::size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(guarded, t);
  guarded(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
}

// work(i) for i in [0, n), on up to `threads` threads (never more than n): item i on thread
// i mod that count. One thread runs the items in order on the caller's, with nothing to set up.
template <typename Work>
void for_each_index(std::size_t n, int threads, Work&& work) {
  const std::size_t workers =
      std::max<std::size_t>(1, std::min(static_cast<std::size_t>(std::max(threads, 1)), n));
  if (workers == 1) {
    for (std::size_t i = 0; i < n; ++i) work(i);
    return;
  }
  run_on_threads(static_cast<int>(workers), [&](int t) {
    for (std::size_t i = static_cast<std::size_t>(t); i < n; i += workers) work(i);
  });
}

}  // namespace loopscan
