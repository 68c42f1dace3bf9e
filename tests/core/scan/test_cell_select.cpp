// best_per_cell (the filters' one-point-per-cell selection) against a brute-force oracle: the
// smallest score per key, the first on ties, cells in order of first occurrence; both the
// double and the compact float cells, over enough calls to wrap the 8-bit generation stamps.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "loopscan/core/scan/cell_select.hpp"

namespace loopscan {
namespace {

std::vector<int> oracle(const std::vector<std::uint32_t>& keys, const std::vector<float>& scores,
                        std::uint32_t max_key) {
  std::map<std::uint32_t, int> best;
  std::vector<std::uint32_t> order;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] > max_key) continue;
    auto it = best.find(keys[i]);
    if (it == best.end()) {
      best[keys[i]] = static_cast<int>(i);
      order.push_back(keys[i]);
    } else if (scores[i] < scores[it->second]) {
      it->second = static_cast<int>(i);
    }
  }
  std::vector<int> out;
  for (std::uint32_t k : order) out.push_back(best[k]);
  return out;
}

TEST(CellSelect, FloatAndDoubleCellsMatchTheOracleAcrossStampWraps) {
  std::mt19937 rng(3);
  std::vector<int> kept_f, kept_d;
  for (int call = 0; call < 600; ++call) {
    const std::uint32_t max_key = call % 3 == 0 ? 450000 : 65000;
    const std::size_t n = 1 + rng() % 3000;
    std::vector<std::uint32_t> keys(n);
    std::vector<float> scores(n);
    for (std::size_t i = 0; i < n; ++i) {
      // Few distinct keys (repeats and ties), some outside every cell.
      keys[i] = rng() % 10 == 0 ? max_key + 1 + rng() % 5 : (rng() % 400) * (max_key / 400);
      scores[i] = static_cast<float>(static_cast<int>(rng() % 50) - 25) * 0.5f;
    }
    const std::vector<int> want = oracle(keys, scores, max_key);
    best_per_cell(keys, scores, max_key, kept_f);
    best_per_cell(keys, std::vector<double>(scores.begin(), scores.end()), max_key, kept_d);
    ASSERT_EQ(kept_f, want) << "call " << call;
    ASSERT_EQ(kept_d, want) << "call " << call;
  }
}

}  // namespace
}  // namespace loopscan
