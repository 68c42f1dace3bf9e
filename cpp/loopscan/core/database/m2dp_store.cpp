// M2DP places: the 4 sign versions x [structure | intensity] rows in float. The index is a
// KD-tree over the structure half of version 0; a query searches it with each of its four
// versions, which covers the sign ambiguity the exact distance minimises over.
#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/key_index.hpp"
#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

constexpr int kVersions = 4;

float dot(const float* a, const float* b, int n) {
  using V = simd::Vec<float, 16>::type;
  V acc0{}, acc1{};
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    acc0 += simd::load<V>(a + i) * simd::load<V>(b + i);
    acc1 += simd::load<V>(a + i + 4) * simd::load<V>(b + i + 4);
  }
  const V acc = acc0 + acc1;
  float s = acc[0] + acc[1] + acc[2] + acc[3];
  for (; i < n; ++i) s += a[i] * b[i];
  return s;
}

class M2dpStore final : public PlaceStore {
  struct RowsQuery : Query {
    std::vector<float> rows;
  };

 public:
  explicit M2dpStore(int columns)
      : PlaceStore(kVersions * static_cast<std::size_t>(std::max(columns, 0))),
        half_(columns / 2),
        index_(std::max(half_, 1)) {
    if (columns <= 0 || columns % 2 != 0) {
      throw std::invalid_argument("M2DP signatures need an even, positive column count");
    }
  }

  int components() const override { return 2; }

  void encode(const Signature& s, float* payload) const override {
    if (s.rows() != kVersions || s.cols() != 2 * half_) {
      throw std::invalid_argument("an M2DP signature must be 4 x " + std::to_string(2 * half_) +
                                  ", got " + std::to_string(s.rows()) + " x " +
                                  std::to_string(s.cols()));
    }
    for (int v = 0; v < kVersions; ++v) {
      for (int c = 0; c < 2 * half_; ++c) payload[v * 2 * half_ + c] = static_cast<float>(s(v, c));
    }
  }
  void indexed_up_to(std::size_t n) override {
    for (std::size_t i = index_.size(); i < n; ++i)
      index_.add(arena_.at(i));  // version 0, structure
  }

  std::unique_ptr<Query> prepare(const Signature& s) const override {
    auto q = std::make_unique<RowsQuery>();
    q->rows.resize(payload_floats());
    encode(s, q->rows.data());
    return q;
  }

  void distances(const Query& query, const float* p, double* out) const override {
    const float* q = static_cast<const RowsQuery&>(query).rows.data();
    for (int c = 0; c < 2; ++c) {
      float best = -std::numeric_limits<float>::infinity();
      for (int qv = 0; qv < kVersions; ++qv) {
        for (int v = 0; v < kVersions; ++v) {
          best = std::max(best, dot(q + (qv * 2 + c) * half_, p + (v * 2 + c) * half_, half_));
        }
      }
      out[c] = (1.0 - double(best)) / 2.0;
    }
  }

  void candidates(const Query& query, std::size_t count, std::size_t /*pool*/,
                  const Eligible& eligible, std::size_t,
                  std::vector<std::size_t>& out) const override {
    const float* q = static_cast<const RowsQuery&>(query).rows.data();
    std::map<std::size_t, float> nearest;  // place -> smallest key distance over versions
    std::vector<std::pair<float, std::size_t>> near;
    for (int qv = 0; qv < kVersions; ++qv) {
      index_.nearest(q + qv * 2 * half_, count, eligible, near);
      for (const auto& [d, i] : near) {
        auto [it, inserted] = nearest.emplace(i, d);
        if (!inserted) it->second = std::min(it->second, d);
      }
    }
    std::vector<std::pair<float, std::size_t>> ranked;
    for (const auto& [i, d] : nearest) ranked.emplace_back(d, i);
    std::sort(ranked.begin(), ranked.end());
    out.clear();
    for (std::size_t j = 0; j < ranked.size() && j < count; ++j) out.push_back(ranked[j].second);
  }

  std::size_t index_bytes() const override { return index_.memory_bytes(); }

 private:
  int half_;
  KeyIndex index_;
};

}  // namespace

std::unique_ptr<PlaceStore> make_m2dp_store(int columns) {
  return std::make_unique<M2dpStore>(columns);
}

}  // namespace loopscan
