#pragma once
// Runs work(t) for t = 0 .. threads-1, thread 0 on the caller's thread. Each worker takes the
// items i = t, t + threads, ... so the split, and therefore every result, is deterministic.
// An exception leaving a worker is kept, every thread is joined, then the first one (lowest t)
// is rethrown: a throwing item (a bad input, a caller's callback) never ends the process.
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

}  // namespace loopscan
