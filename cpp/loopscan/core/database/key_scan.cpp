#include "loopscan/core/database/key_scan.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/nearest_set.hpp"
#include "loopscan/core/simd.hpp"

#if LOOPSCAN_HAVE_AVX2_CLONES
#include <immintrin.h>
#define LOOPSCAN_AVX512BW __attribute__((target("avx2,fma,avx512f,avx512dq,avx512vl,avx512bw")))
#endif

// The block scans at three widths (baseline, AVX2, AVX-512): distances are exact integers
// (uint32), whatever the width or order, and a block stops as soon as every lane is above the
// sink's bound (the sums only grow). Cell centres: every float distance computed.
namespace loopscan::key_scan {
namespace {

using Nearest = NearestSet<std::uint32_t>;

constexpr int kCheck = 4;  // dimension pairs summed between two checks against the bound

// Hands the lanes in `mask` to the sink.
LOOPSCAN_INLINE void emit(unsigned mask, const std::uint32_t* dist, const std::uint32_t* ids,
                          Nearest& sink) {
  for (; mask; mask &= mask - 1) {
    const int l = __builtin_ctz(mask);
    sink.add(dist[l], ids[l]);
  }
}

void scan_base(const BlockRef* blocks, std::size_t n_blocks, int pairs,
               const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      unsigned mask = 0;
      for (int l = 0; l < kBlock; ++l) {
        std::uint32_t s = 0;
        for (int p = 0; p < pairs; ++p) {
          const int e0 = int(keys[(p * kBlock + l) * 2]) - int(q[p] & 0xffffu);
          const int e1 = int(keys[(p * kBlock + l) * 2 + 1]) - int(q[p] >> 16);
          s += static_cast<std::uint32_t>(e0 * e0 + e1 * e1);
        }
        dist[l] = s;
        if (s <= sinks[v].bound()) mask |= 1u << l;
      }
      emit(mask & blocks[b].valid, dist, blocks[b].ids, sinks[v]);
    }
  }
}

#if LOOPSCAN_HAVE_AVX2_CLONES
// acc <= bound as unsigned 32-bit lanes, as a mask of 8 bits.
LOOPSCAN_AVX2 inline unsigned at_most(__m256i acc, __m256i bound) {
  const __m256i le = _mm256_cmpeq_epi32(_mm256_max_epu32(acc, bound), bound);
  return static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(le)));
}

LOOPSCAN_AVX2 void scan_avx2(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                             const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  alignas(32) std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      const __m256i bound = _mm256_set1_epi32(static_cast<int>(sinks[v].bound()));
      __m256i lo = _mm256_setzero_si256(), hi = _mm256_setzero_si256();
      unsigned mask = 0;
      for (int p = 0; p < pairs; ++p) {
        const __m256i qp = _mm256_set1_epi32(static_cast<int>(q[p]));
        const auto* row = reinterpret_cast<const __m256i*>(keys + p * kBlock * 2);
        const __m256i e0 = _mm256_sub_epi16(_mm256_loadu_si256(row), qp);
        const __m256i e1 = _mm256_sub_epi16(_mm256_loadu_si256(row + 1), qp);
        lo = _mm256_add_epi32(lo, _mm256_madd_epi16(e0, e0));
        hi = _mm256_add_epi32(hi, _mm256_madd_epi16(e1, e1));
        if (p % kCheck == kCheck - 1 || p == pairs - 1) {
          mask = blocks[b].valid & (at_most(lo, bound) | at_most(hi, bound) << 8);
          if (!mask) break;
        }
      }
      if (!mask) continue;
      _mm256_store_si256(reinterpret_cast<__m256i*>(dist), lo);
      _mm256_store_si256(reinterpret_cast<__m256i*>(dist + 8), hi);
      emit(mask, dist, blocks[b].ids, sinks[v]);
    }
  }
}

LOOPSCAN_AVX512BW void scan_avx512(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                                   const std::uint32_t* queries, int n_queries, Nearest* sinks) {
  alignas(64) std::uint32_t dist[kBlock];
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const std::uint16_t* keys = blocks[b].keys;
    if (b + 1 < n_blocks) __builtin_prefetch(blocks[b + 1].keys);
    for (int v = 0; v < n_queries; ++v) {
      const std::uint32_t* q = queries + static_cast<std::size_t>(v) * pairs;
      const __m512i bound = _mm512_set1_epi32(static_cast<int>(sinks[v].bound()));
      __m512i acc = _mm512_setzero_si512();
      unsigned mask = 0;
      for (int p = 0; p < pairs; ++p) {
        const __m512i e = _mm512_sub_epi16(_mm512_loadu_si512(keys + p * kBlock * 2),
                                           _mm512_set1_epi32(static_cast<int>(q[p])));
        acc = _mm512_add_epi32(acc, _mm512_madd_epi16(e, e));
        if (p % kCheck == kCheck - 1 || p == pairs - 1) {
          mask = blocks[b].valid & _mm512_cmple_epu32_mask(acc, bound);
          if (!mask) break;
        }
      }
      if (!mask) continue;
      _mm512_store_si512(dist, acc);
      emit(mask, dist, blocks[b].ids, sinks[v]);
    }
  }
}

LOOPSCAN_AVX2 void scan_float_avx2(const FloatBlockRef* blocks, std::size_t n_blocks, int dims,
                                   const float* query, float* out) {
  for (std::size_t b = 0; b < n_blocks; ++b) {
    __m256 lo = _mm256_setzero_ps(), hi = _mm256_setzero_ps();
    for (int d = 0; d < dims; ++d) {
      const __m256 qd = _mm256_set1_ps(query[d]);
      const __m256 e0 = _mm256_sub_ps(_mm256_loadu_ps(blocks[b].keys + d * kBlock), qd);
      const __m256 e1 = _mm256_sub_ps(_mm256_loadu_ps(blocks[b].keys + d * kBlock + 8), qd);
      lo = _mm256_fmadd_ps(e0, e0, lo);
      hi = _mm256_fmadd_ps(e1, e1, hi);
    }
    _mm256_storeu_ps(out + b * kBlock, lo);
    _mm256_storeu_ps(out + b * kBlock + 8, hi);
  }
}
#endif

void scan_float_base(const FloatBlockRef* blocks, std::size_t n_blocks, int dims,
                     const float* query, float* out) {
  for (std::size_t b = 0; b < n_blocks; ++b) {
    for (int l = 0; l < kBlock; ++l) {
      float s = 0.f;
      for (int d = 0; d < dims; ++d) {
        const float e = blocks[b].keys[d * kBlock + l] - query[d];
        s = std::fma(e, e, s);
      }
      out[b * kBlock + l] = s;
    }
  }
}

bool has_avx512bw() {
#if LOOPSCAN_HAVE_AVX2_CLONES
  static const bool yes = simd::has_avx512() && __builtin_cpu_supports("avx512bw");
  return yes;
#else
  return false;
#endif
}

// queries: n_queries x pairs, each pair packed as (even dim) | (odd dim) << 16.
void scan(const BlockRef* blocks, std::size_t n_blocks, int pairs, const std::uint32_t* queries,
          int n_queries, Nearest* sinks) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (has_avx512bw()) return scan_avx512(blocks, n_blocks, pairs, queries, n_queries, sinks);
  if (simd::has_avx2()) return scan_avx2(blocks, n_blocks, pairs, queries, n_queries, sinks);
#endif
  scan_base(blocks, n_blocks, pairs, queries, n_queries, sinks);
}

constexpr std::size_t kStride = 8;
// Below this many places per sought one the pilot's bound would be loose anyway.
constexpr std::size_t kMinPlacesPerCount = 16;

// The same result as scan() into fresh sinks (NearestSet(count, eligible)), sooner on many
// blocks: a pilot scan of every 8th block for the count / 4 nearest gives each sink a bound
// that about 2 count places are expected within, so the full scan keeps only those instead of
// every place closer than the count-th so far; a sink left with fewer than count places
// (a bound too tight) is scanned again without one.
void scan_nearest(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                  const std::uint32_t* queries, int n_queries, std::size_t count, Nearest* sinks) {
  if (count == 0 || n_blocks * kBlock < kMinPlacesPerCount * count) {
    scan(blocks, n_blocks, pairs, queries, n_queries, sinks);
    return;
  }
  // The sample holds 1/8 of the places: its (count / 4)-th distance is about the full set's
  // (2 count)-th.
  std::vector<BlockRef> sample;
  for (std::size_t b = 0; b < n_blocks; b += kStride) sample.push_back(blocks[b]);
  const std::size_t pilot_count = std::max<std::size_t>(1, 2 * count / kStride);
  std::vector<Nearest> pilots;
  pilots.reserve(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) pilots.emplace_back(pilot_count, sinks[v].eligible());
  scan(sample.data(), sample.size(), pairs, queries, n_queries, pilots.data());
  std::vector<bool> bounded(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) {
    bounded[v] = pilots[v].full();
    if (bounded[v]) sinks[v].tighten(pilots[v].bound());
  }
  scan(blocks, n_blocks, pairs, queries, n_queries, sinks);
  for (int v = 0; v < n_queries; ++v) {
    if (!bounded[v] || sinks[v].size() >= count) continue;
    sinks[v] = Nearest(count, sinks[v].eligible());
    scan(blocks, n_blocks, pairs, queries + static_cast<std::size_t>(v) * pairs, 1, &sinks[v]);
  }
}

// out[16 b + l] = squared L2 distance (float, fused multiply-adds in dim order) of lane l of
// block b to query.
void scan_float(const FloatBlockRef* blocks, std::size_t n_blocks, int dims, const float* query,
                float* out) {
#if LOOPSCAN_HAVE_AVX2_CLONES
  if (simd::has_avx2()) return scan_float_avx2(blocks, n_blocks, dims, query, out);
#endif
  scan_float_base(blocks, n_blocks, dims, query, out);
}

}  // namespace
}  // namespace loopscan::key_scan

namespace loopscan {
namespace {

using key_scan::BlockRef;
constexpr int B = KeyScan::kBlock;
constexpr std::uint32_t kBlocksPerChunk = 16;  // 256 places: small maps stay small
constexpr int kTrainingRounds = 8;
constexpr std::size_t kSamplePerCell = 64;

std::uint16_t clamped(std::uint16_t v) { return std::min(v, KeyScan::kMaxKey); }

// About sqrt(n)/2 cells (a power of two, at least 16): cells of ~2 sqrt(n) keys.
std::size_t cells_for(std::size_t n) {
  std::size_t c = 16;
  while (c * c < n / 4) c *= 2;
  return c;
}

}  // namespace

KeyScan::KeyScan(int dims, const KeyScanConfig& config)
    : dims_(dims),
      pairs_((dims + 1) / 2),
      config_(config),
      next_layout_(std::min<std::size_t>(256, std::max<std::size_t>(1, config.cells_from))) {
  if (dims < 1 || dims > kMaxDims) {
    throw std::invalid_argument("KeyScan: keys need 1.." + std::to_string(kMaxDims) +
                                " dimensions, got " + std::to_string(dims));
  }
  cells_.resize(1);
  order_.resize(dims);
  std::iota(order_.begin(), order_.end(), 0);
}
KeyScan::~KeyScan() = default;

std::uint16_t* KeyScan::block_keys(std::uint32_t b) const {
  return key_chunks_[b / kBlocksPerChunk].get() +
         static_cast<std::size_t>(b % kBlocksPerChunk) * pairs_ * B * 2;
}
std::uint32_t* KeyScan::block_ids(std::uint32_t b) const {
  return id_chunks_[b / kBlocksPerChunk].get() + static_cast<std::size_t>(b % kBlocksPerChunk) * B;
}
BlockRef KeyScan::ref(const Cell& cell, std::size_t j) const {
  const int lanes = j + 1 == cell.blocks.size() ? cell.fill : B;
  return {block_keys(cell.blocks[j]), block_ids(cell.blocks[j]), simd::first_lanes(lanes)};
}

void KeyScan::place(std::uint32_t c, const std::uint16_t* key, std::uint32_t id) {
  Cell& cell = cells_[c];
  if (cell.blocks.empty() || cell.fill == B) {
    if (n_blocks_ % kBlocksPerChunk == 0) {
      key_chunks_.emplace_back(new std::uint16_t[kBlocksPerChunk * pairs_ * B * 2]());
      id_chunks_.emplace_back(new std::uint32_t[kBlocksPerChunk * B]());
    }
    cell.blocks.push_back(n_blocks_++);
    cell.fill = 0;
  }
  std::uint16_t* keys = block_keys(cell.blocks.back());
  for (int j = 0; j < dims_; ++j) {
    keys[((j / 2) * B + cell.fill) * 2 + j % 2] = clamped(key[order_[j]]);
  }
  block_ids(cell.blocks.back())[cell.fill] = id;
  ++cell.fill;
}

void KeyScan::set_centres(std::vector<float> centres) {
  centres_ = std::move(centres);
  const std::size_t n = centres_.size() / dims_, n_blocks = (n + B - 1) / B;
  centre_keys_.assign(n_blocks * dims_ * B, 0.f);
  centre_refs_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < dims_; ++d) {
      centre_keys_[(i / B) * dims_ * B + d * B + i % B] = centres_[i * dims_ + d];
    }
  }
  for (std::size_t b = 0; b < n_blocks; ++b) {
    const int lanes = static_cast<int>(std::min<std::size_t>(B, n - b * B));
    centre_refs_.push_back({&centre_keys_[b * dims_ * B], simd::first_lanes(lanes)});
  }
}

void KeyScan::centre_distances(const float* key, float* out) const {
  key_scan::scan_float(centre_refs_.data(), centre_refs_.size(), dims_, key, out);
}

std::uint32_t KeyScan::nearest_cell(const float* key) const {
  if (centres_.empty()) return 0;
  thread_local std::vector<float> d;
  d.resize(centre_refs_.size() * B);
  centre_distances(key, d.data());
  return static_cast<std::uint32_t>(std::min_element(d.begin(), d.begin() + cells_.size()) -
                                    d.begin());  // the first of equals
}

void KeyScan::add(const std::uint16_t* key) {
  std::uint32_t cell = 0;
  if (!centres_.empty()) {
    float k[kMaxDims];
    for (int d = 0; d < dims_; ++d) k[d] = clamped(key[d]);
    cell = nearest_cell(k);
  }
  place(cell, key, static_cast<std::uint32_t>(count_));
  ++count_;
  if (count_ == next_layout_) lay_out();
}

void KeyScan::lay_out() {
  // Every key in id order.
  std::vector<std::uint16_t> all(count_ * dims_);
  for (const Cell& cell : cells_) {
    for (std::size_t j = 0; j < cell.blocks.size(); ++j) {
      const BlockRef r = ref(cell, j);
      for (int l = 0; l < B; ++l) {
        if (!(r.valid >> l & 1u)) continue;
        for (int t = 0; t < dims_; ++t) {
          all[r.ids[l] * std::size_t(dims_) + order_[t]] = r.keys[((t / 2) * B + l) * 2 + t % 2];
        }
      }
    }
  }
  // Dimensions by decreasing variance, so the first pairs already set most places apart and
  // a block is left after a few of them (distances are exact sums: the order changes no bits).
  std::vector<double> mean(dims_, 0.0), var(dims_, 0.0);
  for (std::size_t i = 0; i < count_; ++i) {
    for (int t = 0; t < dims_; ++t) mean[t] += all[i * dims_ + t];
  }
  for (double& m : mean) m /= double(count_);
  for (std::size_t i = 0; i < count_; ++i) {
    for (int t = 0; t < dims_; ++t) var[t] += std::pow(all[i * dims_ + t] - mean[t], 2);
  }
  std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return var[a] > var[b]; });
  if (count_ >= config_.cells_from) train(all);
  key_chunks_.clear();
  id_chunks_.clear();
  n_blocks_ = 0;
  for (Cell& c : cells_) c = Cell{};
  std::vector<float> key(dims_);
  for (std::size_t i = 0; i < count_; ++i) {
    std::copy_n(&all[i * dims_], dims_, key.data());
    place(nearest_cell(key.data()), &all[i * dims_], static_cast<std::uint32_t>(i));
  }
  // Every 4x below cells_from (stopping at it), every 2x from it on (a retraining each time).
  next_layout_ =
      count_ < config_.cells_from ? std::min(4 * count_, config_.cells_from) : 2 * count_;
}

void KeyScan::train(const std::vector<std::uint16_t>& all) {
  const std::vector<float> keys(all.begin(), all.end());
  // Lloyd's k-means on an evenly spread sample, seeded with evenly spread sample keys
  // (deterministic); a cell left empty keeps its centre.
  const std::size_t C = cells_for(count_);
  const std::size_t step = std::max<std::size_t>(1, count_ / (kSamplePerCell * C));
  std::vector<std::size_t> sample;
  for (std::size_t i = 0; i < count_; i += step) sample.push_back(i);
  std::vector<float> centres(C * dims_);
  for (std::size_t c = 0; c < C; ++c) {
    std::copy_n(&keys[sample[c * sample.size() / C] * dims_], dims_, &centres[c * dims_]);
  }
  cells_.assign(C, Cell{});  // nearest_cell() reads the count of cells
  for (int round = 0; round < kTrainingRounds; ++round) {
    set_centres(centres);
    std::vector<double> sums(C * dims_, 0.0);
    std::vector<std::size_t> sizes(C, 0);
    for (std::size_t i : sample) {
      const std::size_t c = nearest_cell(&keys[i * dims_]);
      ++sizes[c];
      for (int t = 0; t < dims_; ++t) sums[c * dims_ + t] += keys[i * dims_ + t];
    }
    for (std::size_t c = 0; c < C; ++c) {
      if (sizes[c] == 0) continue;
      for (int t = 0; t < dims_; ++t) {
        centres[c * dims_ + t] = static_cast<float>(sums[c * dims_ + t] / double(sizes[c]));
      }
    }
  }
  set_centres(std::move(centres));
}

std::uint32_t KeyScan::distance(const std::uint16_t* a, const std::uint16_t* b, int dims) {
  std::uint32_t s = 0;
  for (int d = 0; d < dims; ++d) {
    const int e = int(clamped(a[d])) - int(clamped(b[d]));
    s += static_cast<std::uint32_t>(e * e);
  }
  return s;
}

void KeyScan::nearest(const std::uint16_t* queries, int n_queries, std::size_t count,
                      const std::function<bool(std::size_t)>& eligible,
                      std::vector<Neighbours>& out) const {
  out.resize(static_cast<std::size_t>(std::max(0, n_queries)));
  for (auto& o : out) o.clear();
  if (count == 0 || count_ == 0 || n_queries <= 0) return;
  // Queries in dimension pairs, as the blocks hold them.
  std::vector<std::uint32_t> packed(static_cast<std::size_t>(n_queries) * pairs_, 0u);
  for (int v = 0; v < n_queries; ++v) {
    for (int d = 0; d < dims_; ++d) {
      packed[v * pairs_ + d / 2] |= std::uint32_t{clamped(queries[v * dims_ + order_[d]])}
                                    << 16 * (d % 2);
    }
  }
  std::vector<key_scan::Nearest> sinks;
  sinks.reserve(static_cast<std::size_t>(n_queries));
  for (int v = 0; v < n_queries; ++v) sinks.emplace_back(count, eligible);
  std::vector<BlockRef> refs;
  auto add_cell = [&](const Cell& cell) {
    for (std::size_t j = 0; j < cell.blocks.size(); ++j) refs.push_back(ref(cell, j));
  };
  if (cells_.size() == 1) {  // every key, every query key in one pass
    add_cell(cells_[0]);
    key_scan::scan_nearest(refs.data(), refs.size(), pairs_, packed.data(), n_queries, count,
                           sinks.data());
  } else {
    // Per query key, its nearest cells until probe_factor x count keys are seen.
    std::vector<float> d(centre_refs_.size() * B), q(dims_);
    std::vector<std::pair<float, std::uint32_t>> order(cells_.size());
    const std::size_t enough = std::max<std::size_t>(1, config_.probe_factor) * count;
    for (int v = 0; v < n_queries; ++v) {
      for (int t = 0; t < dims_; ++t) q[t] = clamped(queries[v * dims_ + t]);
      centre_distances(q.data(), d.data());
      for (std::uint32_t c = 0; c < cells_.size(); ++c) order[c] = {d[c], c};
      std::sort(order.begin(), order.end());
      refs.clear();
      std::size_t seen = 0;
      for (const auto& [dist, c] : order) {
        if (seen >= enough) break;
        add_cell(cells_[c]);
        if (!cells_[c].blocks.empty()) seen += (cells_[c].blocks.size() - 1) * B + cells_[c].fill;
      }
      key_scan::scan_nearest(refs.data(), refs.size(), pairs_, &packed[v * pairs_], 1, count,
                             &sinks[v]);
    }
  }
  for (int v = 0; v < n_queries; ++v) sinks[v].finish(out[v]);
}

std::size_t KeyScan::memory_bytes() const {
  std::size_t bytes = key_chunks_.size() * kBlocksPerChunk * B * (pairs_ * 4 + 4);
  for (const Cell& c : cells_) bytes += sizeof(Cell) + c.blocks.capacity() * 4;
  return bytes + (centres_.capacity() + centre_keys_.capacity()) * 4 +
         centre_refs_.capacity() * sizeof(key_scan::FloatBlockRef);
}

}  // namespace loopscan
