// DELIGHT places: the 16 region histograms in float plus their totals. The index is a coarse
// prefilter compared by chi-square against every eligible place: the regions summed over the
// orbits of the four sign-flip permutations (r -> r ^ m, m in {0, 5, 6, 3}: 4 orbits of 4
// regions, so the key is invariant to the flips), each in 16 wide bins.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/matching/delight_packed.hpp"
#include "loopscan/core/matching/pair_distance.hpp"

namespace loopscan {
namespace {

constexpr int kOrbits = 4, kOrbitBins = 16, kCoarseBins = kOrbits * kOrbitBins;

// Orbit of each region under r -> r ^ m, m in {0, 5, 6, 3} (kDelightRegionMasks): 4 orbits,
// numbered in the order of their smallest members 0, 1, 8, 9.
constexpr int kOrbit[kDelightRegions] = {0, 1, 1, 0, 1, 0, 0, 1, 2, 3, 3, 2, 3, 2, 2, 3};

constexpr bool orbits_are_closed() {
  for (int r = 0; r < kDelightRegions; ++r) {
    for (int m : kDelightRegionMasks) {
      if (kOrbit[r] != kOrbit[r ^ m]) return false;
    }
  }
  return true;
}
static_assert(orbits_are_closed(), "kOrbit must be invariant under the region flips");

class DelightStore final : public PlaceStore {
  struct HistogramQuery : Query {
    std::vector<float> payload;
    float coarse[kCoarseBins];
  };

 public:
  explicit DelightStore(int columns)
      : PlaceStore(kDelightRegions * static_cast<std::size_t>(delight_padded_bins(columns)) + 2),
        columns_(columns),
        bins_(delight_padded_bins(columns)) {
    if (columns <= 0) throw std::invalid_argument("DELIGHT signatures need columns > 0");
  }

  // Payload: [region][padded bin] counts, then the two totals.
  int components() const override { return 1; }

  void encode(const Signature& s, float* payload) const override {
    if (s.rows() != kDelightRegions || s.cols() != columns_) {
      throw std::invalid_argument("a DELIGHT signature must be 16 x " + std::to_string(columns_) +
                                  ", got " + std::to_string(s.rows()) + " x " +
                                  std::to_string(s.cols()));
    }
    const DelightTotals t = delight_pack(s, bins_, payload);
    payload[kDelightRegions * bins_] = static_cast<float>(t.sum);
    payload[kDelightRegions * bins_ + 1] = static_cast<float>(t.nonzero);
  }

  void indexed_up_to(std::size_t n) override {
    for (std::size_t i = coarse_.size() / kCoarseBins; i < n; ++i) {
      float c[kCoarseBins];
      coarse_of(record(i), c);
      coarse_.insert(coarse_.end(), c, c + kCoarseBins);
    }
  }

  std::unique_ptr<Query> prepare(const Signature& s) const override {
    auto q = std::make_unique<HistogramQuery>();
    q->payload.resize(payload_floats());
    encode(s, q->payload.data());
    coarse_of(q->payload.data(), q->coarse);
    return q;
  }

  void distances(const Query& query, const float* p, double* out) const override {
    const float* q = static_cast<const HistogramQuery&>(query).payload.data();
    out[0] = delight_packed_distance(q, totals(q), p, totals(p), bins_);
  }

  void candidates(const Query& query, std::size_t count, std::size_t /*pool*/,
                  const Eligible& eligible, std::size_t n_places,
                  std::vector<std::size_t>& out) const override {
    const float* qc = static_cast<const HistogramQuery&>(query).coarse;
    std::vector<std::pair<float, std::size_t>> scored;
    for (std::size_t i = 0; i < n_places; ++i) {
      if (!eligible(i)) continue;
      const float* c = &coarse_[i * kCoarseBins];
      float chi = 0;
      for (int b = 0; b < kCoarseBins; ++b) {
        const float s = qc[b] + c[b], d = qc[b] - c[b];
        chi += s > 0 ? d * d / s : 0.f;
      }
      scored.emplace_back(chi, i);
    }
    const std::size_t n = std::min(count, scored.size());
    std::partial_sort(scored.begin(), scored.begin() + n, scored.end());
    out.clear();
    for (std::size_t j = 0; j < n; ++j) out.push_back(scored[j].second);
  }

  std::size_t index_bytes() const override { return coarse_.capacity() * sizeof(float); }

 private:
  DelightTotals totals(const float* p) const {
    return {p[kDelightRegions * bins_], p[kDelightRegions * bins_ + 1]};
  }
  void coarse_of(const float* p, float* c) const {
    std::fill(c, c + kCoarseBins, 0.f);
    const int width = (columns_ + kOrbitBins - 1) / kOrbitBins;
    for (int r = 0; r < kDelightRegions; ++r) {
      float* o = c + kOrbit[r] * kOrbitBins;
      for (int b = 0; b < columns_; ++b) o[b / width] += p[r * bins_ + b];
    }
    const float total = p[kDelightRegions * bins_];
    if (total > 0) {
      for (int b = 0; b < kCoarseBins; ++b) c[b] /= total;
    }
  }

  int columns_, bins_;
  std::vector<float> coarse_;  // kCoarseBins per place, normalised to sum 1
};

}  // namespace

std::unique_ptr<PlaceStore> make_delight_store(int columns) {
  return std::make_unique<DelightStore>(columns);
}

}  // namespace loopscan
