#include "loopscan/core/cell_select.hpp"

namespace loopscan {
namespace {

// One stable counting-sort pass of `in` (point indices) by `bits` bits of the key at `shift`.
void radix_pass(const std::vector<std::uint32_t>& keys, const std::vector<std::uint32_t>& in,
                std::vector<std::uint32_t>& out, int shift, int bits,
                std::vector<std::uint32_t>& count) {
  const std::uint32_t mask = (1u << bits) - 1;
  count.assign(static_cast<std::size_t>(mask) + 2, 0);
  for (std::uint32_t i : in) ++count[((keys[i] >> shift) & mask) + 1];
  for (std::size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
  out.resize(in.size());
  for (std::uint32_t i : in) out[count[(keys[i] >> shift) & mask]++] = i;
}

}  // namespace

void best_per_cell(const std::vector<std::uint32_t>& keys, const std::vector<double>& scores,
                   std::uint32_t max_key, std::vector<int>& kept) {
  thread_local std::vector<std::uint32_t> a, b, count;
  const std::size_t n = keys.size();
  int bits = 1;
  while (bits < 32 && (max_key >> bits) != 0) ++bits;
  const int low = (bits + 1) / 2, high = bits - low;
  a.resize(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = static_cast<std::uint32_t>(i);
  radix_pass(keys, a, b, 0, low, count);
  if (high > 0) {
    radix_pass(keys, b, a, low, high, count);
  } else {
    a.swap(b);
  }
  kept.clear();
  for (std::size_t s = 0; s < n;) {
    const std::uint32_t key = keys[a[s]];
    std::uint32_t best = a[s];
    for (++s; s < n && keys[a[s]] == key; ++s) {
      best = scores[a[s]] < scores[best] ? a[s] : best;
    }
    kept.push_back(static_cast<int>(best));
  }
}

}  // namespace loopscan
