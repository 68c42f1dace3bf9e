#pragma once
// Runs work(t) for t = 0 .. threads-1, thread 0 on the caller's thread. Each worker takes the
// items i = t, t + threads, ... so the split, and therefore every result, is deterministic.
#include <thread>
#include <vector>

namespace loopscan {

template <typename Work>
void run_on_threads(int threads, Work&& work) {
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& th : pool) th.join();
}

}  // namespace loopscan
