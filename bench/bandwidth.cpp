// Copy bandwidth of one core for buffers that live in L2, in L3 and in memory: the figures
// bench/README.md divides bytes by. Standalone (no CMake target):
//   g++ -O2 -o /tmp/bandwidth bench/bandwidth.cpp && /tmp/bandwidth
// Reports the best of 5 runs of memcpy over each size (bytes read + bytes written per second).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

int main() {
  for (std::size_t bytes : {std::size_t(256) << 10, std::size_t(8) << 20, std::size_t(512) << 20}) {
    std::vector<char> a(bytes, 1), b(bytes, 2);
    const int reps = static_cast<int>(std::max<std::size_t>(1, (std::size_t(2) << 30) / bytes));
    double best = 1e30;
    for (int run = 0; run < 5; ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int r = 0; r < reps; ++r) {
        std::memcpy(r % 2 ? a.data() : b.data(), r % 2 ? b.data() : a.data(), bytes);
      }
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      best = std::min(best, s);
    }
    std::printf("%8zu KiB: %.1f GB/s (read + write)\n", bytes >> 10,
                2.0 * double(bytes) * reps / best / 1e9);
  }
  return 0;
}
