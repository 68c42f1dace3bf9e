// Scan Context places: packed spectra (scan_context_spectra.hpp) followed by a quantised
// spectral key. Retrieval has two index stages before exact scoring:
//  1. the nearest places by a coarse key: Scan Context's ring key (per ring the sector sum of
//     the normalised structure half, i.e. each ring's DC term) and the intensity half's
//     (2R-D), found for every query version at once (key_scan.hpp: one pass over all keys, or
//     over the nearest cells of an inverted file from 32k places on);
//  2. those candidates re-ranked by a richer rotation-invariant key: for both halves and
//     every ring, the DC term and the magnitudes of the two lowest harmonics (120-D).
// The 120-D key is stored quantised (uint16) after the spectra, ring key first; the scan keeps
// its own copy of the coarse key. With PlaceStorage::Compact the spectra are stored
// as bytes (compact_spectra.hpp) and expanded before scoring.
// On the simulated city the ring key alone put the exact best place among 50 candidates for
// ~40% of same-season queries and ~89% across seasons; the two stages with the earlier 10-D
// tree key reached ~65% and ~99% (docs/database.md).
#include "loopscan/core/database/scan_context_store.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "loopscan/core/database/compact_spectra.hpp"
#include "loopscan/core/database/key_scan.hpp"
#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

// |d|^2 < 2^32 fits a uint32; the sum a uint64. The oracle of the AVX2 kernel and its tail.
LOOPSCAN_INLINE std::uint64_t key_distance_impl(const std::uint16_t* __restrict a,
                                                const std::uint16_t* __restrict b, std::size_t n) {
  std::uint64_t e = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const std::uint32_t d = a[t] > b[t] ? a[t] - b[t] : b[t] - a[t];
    e += static_cast<std::uint64_t>(d * d);
  }
  return e;
}
std::uint64_t key_distance_base(const std::uint16_t* a, const std::uint16_t* b, std::size_t n) {
  return key_distance_impl(a, b, n);
}
#if LOOPSCAN_HAVE_AVX2_CLONES
// 16 dimensions a step: |a - b| as uint16 (max - min), its square split into 16-bit halves by
// mullo / mulhi and re-joined as uint32 lanes, summed in uint64 lanes: exact, as the scalar.
LOOPSCAN_AVX2 std::uint64_t key_distance_avx2(const std::uint16_t* a, const std::uint16_t* b,
                                              std::size_t n) {
  const __m256i low32 = _mm256_set1_epi64x(0xffffffff);
  __m256i acc = _mm256_setzero_si256();
  std::size_t t = 0;
  for (; t + 16 <= n; t += 16) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + t));
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + t));
    const __m256i d = _mm256_sub_epi16(_mm256_max_epu16(x, y), _mm256_min_epu16(x, y));
    const __m256i lo = _mm256_mullo_epi16(d, d), hi = _mm256_mulhi_epu16(d, d);
    for (const __m256i sq : {_mm256_unpacklo_epi16(lo, hi), _mm256_unpackhi_epi16(lo, hi)}) {
      acc = _mm256_add_epi64(acc, _mm256_and_si256(sq, low32));
      acc = _mm256_add_epi64(acc, _mm256_srli_epi64(sq, 32));
    }
  }
  alignas(32) std::uint64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), acc);
  return lanes[0] + lanes[1] + lanes[2] + lanes[3] + key_distance_impl(a + t, b + t, n - t);
}
#endif

int coarse_group(int rings) { return (2 * rings + KeyScan::kMaxDims - 1) / KeyScan::kMaxDims; }

}  // namespace

std::uint64_t spectral_key_distance(const std::uint16_t* a, const std::uint16_t* b, std::size_t n) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const auto kernel = simd::has_avx2() ? key_distance_avx2 : key_distance_base;
  return kernel(a, b, n);
#else
  return key_distance_base(a, b, n);
#endif
}

int coarse_key_dims(int rings) {
  const int g = coarse_group(rings);
  return 2 * ((rings + g - 1) / g);
}

std::vector<std::uint16_t> coarse_key(const std::vector<std::uint16_t>& spectral_key, int rings) {
  // Spectral key layout: the R structure DC terms, the structure harmonics (R x F), then per
  // intensity ring its DC term and harmonics.
  const int R = rings, per_ring = 1 + kSpectralKeyFrequencies, g = coarse_group(R);
  const int intensity = R + (per_ring - 1) * R;
  std::vector<std::uint16_t> out;
  for (int half = 0; half < 2; ++half) {
    for (int r0 = 0; r0 < R; r0 += g) {
      std::uint32_t sum = 0;
      const int end = std::min(R, r0 + g);
      for (int r = r0; r < end; ++r) {
        sum += half == 0 ? spectral_key[r] : spectral_key[intensity + per_ring * r];
      }
      out.push_back(static_cast<std::uint16_t>(sum / static_cast<std::uint32_t>(end - r0) >> 3));
    }
  }
  return out;
}

namespace {

constexpr int kKeyFrequencies = kSpectralKeyFrequencies;
constexpr float kKeyScale = 8192.f;  // quantisation of the spectral key (see spectral_key)

class ScanContextStore final : public PlaceStore {
  // Index keys of one query version.
  struct Keys {
    std::vector<std::uint16_t> coarse;
    std::vector<std::uint16_t> key;
  };
  // One version per signature row (lateral versions, ScanContextConfig); a place is stored by
  // the first row only.
  struct SpectraQuery : Query {
    std::vector<ScanContextSpectra::Query> versions;
    std::vector<Keys> keys;  // per version
    // Per place of the last candidates() output: the versions whose search proposed it.
    mutable std::vector<std::uint32_t> proposed_by;
  };

 public:
  ScanContextStore(const ScanContextConfig& config, PlaceStorage storage)
      : PlaceStore(record_floats(config, storage) + key_floats(config),
                   record_floats(config, storage), value_floats(config, storage)),
        spectra_(config),
        compact_(storage == PlaceStorage::Compact),
        shape_{2 * config.rings, config.sectors},
        key_dims_(key_dims(config)),
        keys_(key_floats(config)),
        index_(coarse_key_dims(config.rings)) {}

  int components() const override { return 2; }

  void encode(const Signature& signature, float* payload) const override {
    AlignedFloats packed(spectra_.floats_per_place());
    spectra_.pack(signature.topRows(1), packed.data());
    const std::vector<std::uint16_t> key = spectral_key(packed.data());
    const std::size_t record =
        static_cast<std::size_t>(payload_floats_) - keys_.floats_per_record();
    if (compact_) {
      compress_spectra(shape_, packed.data(), payload);
    } else {
      std::copy(packed.data(), packed.data() + record, payload);
    }
    std::memset(payload + record, 0, keys_.floats_per_record() * sizeof(float));
    std::memcpy(payload + record, key.data(), key.size() * 2);
  }
  // The spectra are the scoring record; the spectral keys live in their own arena, so the
  // re-ranking of hundreds of candidates reads 240 contiguous bytes each, not a 9.6 KB record.
  void append(const float* payload) override {
    arena_.append(payload);
    keys_.append(payload + arena_.floats_per_record());
  }
  void stored(std::size_t i, float* out) const override {
    std::copy(arena_.at(i), arena_.at(i) + arena_.floats_per_record(), out);
    std::copy(keys_.at(i), keys_.at(i) + keys_.floats_per_record(),
              out + arena_.floats_per_record());
  }
  std::size_t memory_bytes() const override {
    return arena_.memory_bytes() + keys_.memory_bytes() + index_bytes();
  }
  void indexed_up_to(std::size_t n) override {
    std::vector<std::uint16_t> key(key_dims_);
    for (std::size_t i = index_.size(); i < n; ++i) {
      std::memcpy(key.data(), keys_.at(i), key_dims_ * 2);
      index_.add(coarse_key(key, spectra_.rings()).data());
    }
  }

  std::unique_ptr<Query> prepare(const Signature& signature) const override {
    auto q = std::make_unique<SpectraQuery>();
    q->versions = spectra_.prepare_versions(signature);
    for (const ScanContextSpectra::Query& v : q->versions) {
      Keys k;
      k.key = spectral_key(v.packed.data());
      k.coarse = coarse_key(k.key, spectra_.rings());
      q->keys.push_back(std::move(k));
    }
    return q;
  }

  void distances(const Query& query, const float* payload, double* out) const override {
    score(static_cast<const SpectraQuery&>(query), ~0u, payload, out);
  }
  bool partial_first_pass(const Query& query) const override {
    return static_cast<const SpectraQuery&>(query).versions.size() > 1;
  }
  void first_pass(const Query& query, std::size_t slot, const float* payload,
                  double* out) const override {
    const auto& q = static_cast<const SpectraQuery&>(query);
    score(q, slot < q.proposed_by.size() ? q.proposed_by[slot] : ~0u, payload, out);
  }

  void candidates(const Query& query, std::size_t count, std::size_t pool, const Eligible& eligible,
                  std::size_t, std::vector<std::size_t>& out) const override {
    // Each version's nearest ring keys re-ranked by its spectral key; the union of every
    // version's best `count` (a lateral version's own best places must not be crowded out by
    // the centred one's near misses, nor the other way round).
    out.clear();
    const auto& sq = static_cast<const SpectraQuery&>(query);
    std::vector<std::pair<std::size_t, std::uint32_t>> proposals;  // place, version bit
    std::vector<KeyScan::Neighbours> pools;
    std::vector<std::pair<std::int64_t, std::size_t>> ranked;
    std::vector<std::uint16_t> coarse, key(key_dims_);
    for (const Keys& k : sq.keys) coarse.insert(coarse.end(), k.coarse.begin(), k.coarse.end());
    index_.nearest(coarse.data(), static_cast<int>(sq.keys.size()), std::max(count, pool), eligible,
                   pools);
    for (std::size_t v = 0; v < sq.keys.size(); ++v) {
      const Keys& q = sq.keys[v];
      const auto& near = pools[v];
      ranked.clear();
      const std::size_t dims = key_dims_;
      // The candidates' keys are scattered over the arena: fetch a few ahead.
      constexpr std::size_t kAhead = 8;
      auto prefetch = [&](std::size_t j) {
        const char* p = reinterpret_cast<const char*>(keys_.at(near[j].second));
        for (std::size_t b = 0; b < dims * 2; b += 64) __builtin_prefetch(p + b);
      };
      for (std::size_t j = 0; j < std::min(kAhead, near.size()); ++j) prefetch(j);
      for (std::size_t j = 0; j < near.size(); ++j) {
        if (j + kAhead < near.size()) prefetch(j + kAhead);
        const std::size_t i = near[j].second;
        std::memcpy(key.data(), keys_.at(i), dims * 2);
        ranked.emplace_back(
            static_cast<std::int64_t>(spectral_key_distance(q.key.data(), key.data(), dims)), i);
      }
      const std::size_t n = std::min(count, ranked.size());
      std::partial_sort(ranked.begin(), ranked.begin() + n, ranked.end());
      for (std::size_t j = 0; j < n; ++j) {
        proposals.emplace_back(ranked[j].second, v < 32 ? 1u << v : ~0u);
      }
    }
    std::sort(proposals.begin(), proposals.end());
    sq.proposed_by.clear();
    for (const auto& [i, bit] : proposals) {
      if (out.empty() || out.back() != i) {
        out.push_back(i);
        sq.proposed_by.push_back(0);
      }
      sq.proposed_by.back() |= bit;
    }
  }

  std::optional<SectorAlignment> align(const Query& query, const float* payload) const override {
    // The version that matches the structure half best, aligned in double. The float kernel
    // screens the versions first: only those within kScreen of the best can win in double.
    constexpr float kScreen = 1e-3f;
    const auto& versions = static_cast<const SpectraQuery&>(query).versions;
    const float* spectra = expanded(payload);
    std::vector<float> dots(versions.size());
    float top = -2.f, d[2];
    for (std::size_t v = 0; v < versions.size(); ++v) {
      spectra_.best_dots(versions[v], spectra, d);
      dots[v] = d[0];
      top = std::max(top, d[0]);
    }
    std::optional<SectorAlignment> best;
    for (std::size_t v = 0; v < versions.size(); ++v) {
      if (dots[v] < top - kScreen) continue;
      const SectorAlignment a = spectra_.align(versions[v], spectra, 0);
      if (!best || a.dot > best->dot) best = a;
    }
    return best;
  }
  int sectors() const override { return spectra_.sectors(); }
  std::size_t index_bytes() const override { return index_.memory_bytes(); }

 private:
  static std::size_t spectra_floats(const ScanContextConfig& c) {
    return 2 * static_cast<std::size_t>(c.rings) * c.sectors;
  }
  static std::size_t record_floats(const ScanContextConfig& c, PlaceStorage storage) {
    return storage == PlaceStorage::Compact ? CompactSpectraShape{2 * c.rings, c.sectors}.floats()
                                            : spectra_floats(c);
  }
  // The leading floats of a record that are values (the rest of a compact one: bytes).
  static std::size_t value_floats(const ScanContextConfig& c, PlaceStorage storage) {
    return storage == PlaceStorage::Compact ? 2 * static_cast<std::size_t>(c.rings)
                                            : spectra_floats(c);
  }
  // The float spectra of a record: itself, or a compact one expanded into a per-thread buffer.
  const float* expanded(const float* record) const {
    if (!compact_) return record;
    thread_local AlignedFloats buffer;
    if (buffer.size() < shape_.packed_floats()) buffer = AlignedFloats(shape_.packed_floats());
    expand_spectra(shape_, record, buffer.data());
    return buffer.data();
  }
  // Best dots over the query versions in `versions` (a bit per version; bits past 31 mean all).
  void score(const SpectraQuery& q, std::uint32_t versions, const float* record,
             double* out) const {
    const float* spectra = expanded(record);
    float best[2] = {-2.f, -2.f}, dots[2];
    for (std::size_t v = 0; v < q.versions.size(); ++v) {
      if (v < 32 && !(versions >> v & 1u)) continue;
      spectra_.best_dots(q.versions[v], spectra, dots);
      best[0] = std::max(best[0], dots[0]);
      best[1] = std::max(best[1], dots[1]);
    }
    out[0] = (1.0 - double(best[0])) / 2.0;
    out[1] = (1.0 - double(best[1])) / 2.0;
  }
  static std::size_t key_floats(const ScanContextConfig& c) { return (key_dims(c) + 1) / 2; }
  static std::size_t key_dims(const ScanContextConfig& c) {
    return static_cast<std::size_t>(ScanContextSpectra::key_dims(c.rings, kKeyFrequencies));
  }
  // Values of a normalised half lie in [0, sqrt(S)]; 1/8192 steps up to 8 cover the default
  // 60 sectors (sqrt(60) = 7.7) with a step far below the key differences that matter.
  std::vector<std::uint16_t> spectral_key(const float* packed) const {
    const int dims = ScanContextSpectra::key_dims(spectra_.rings(), kKeyFrequencies);
    const int per_ring = 1 + kKeyFrequencies, R = spectra_.rings();
    std::vector<std::uint16_t> key;
    key.reserve(dims);
    auto push = [&](int d) {
      const float v = spectra_.key(packed, d, kKeyFrequencies) * kKeyScale;
      key.push_back(static_cast<std::uint16_t>(std::clamp(v + 0.5f, 0.f, 65535.f)));
    };
    for (int r = 0; r < R; ++r) push(r * per_ring);  // the ring key: structure DC terms
    for (int d = 0; d < dims; ++d) {
      if (d >= R * per_ring || d % per_ring != 0) push(d);
    }
    return key;
  }

  ScanContextSpectra spectra_;
  bool compact_;
  CompactSpectraShape shape_;
  std::size_t key_dims_;
  PayloadArena keys_;  // quantised spectral keys, ring key first (uint16 pairs in floats)
  KeyScan index_;      // the coarse keys (2R-D), searched for all versions at once
};

}  // namespace

std::unique_ptr<PlaceStore> make_scan_context_store(const ScanContextConfig& config,
                                                    PlaceStorage storage) {
  return std::make_unique<ScanContextStore>(config, storage);
}

}  // namespace loopscan
