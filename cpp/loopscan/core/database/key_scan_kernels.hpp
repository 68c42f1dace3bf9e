#pragma once
// The block scans of key_scan.hpp at three widths (baseline, AVX2, AVX-512).
// Places: blocks of 16 keys of 13-bit integers, stored in dimension pairs ([pair][lane][2]
// uint16), so one multiply-add of 16-bit lanes squares and sums two dimensions of 16 places;
// distances are exact integers (uint32), whatever the width or order, and a block stops as
// soon as every lane is above the sink's bound (the sums only grow).
// Cell centres: blocks of float keys ([dim][lane]), every distance computed.
#include <cstddef>
#include <cstdint>
#include <limits>

namespace loopscan::key_scan {

constexpr int kBlock = 16;
constexpr std::uint16_t kMaxKey = 8191;  // 64 dims of squared 13-bit differences fit a uint32

struct BlockRef {
  const std::uint16_t* keys;  // [pair][lane][2]
  const std::uint32_t* ids;   // [lane]
  std::uint32_t valid;        // lane mask
};
struct FloatBlockRef {
  const float* keys;  // [dim][lane]
  std::uint32_t valid;
};

}  // namespace loopscan::key_scan
namespace loopscan {
template <class Distance>
class NearestSet;  // nearest_set.hpp
}  // namespace loopscan
namespace loopscan::key_scan {
using Nearest = NearestSet<std::uint32_t>;

// queries: n_queries x pairs, each pair packed as (even dim) | (odd dim) << 16.
void scan(const BlockRef* blocks, std::size_t n_blocks, int pairs, const std::uint32_t* queries,
          int n_queries, Nearest* sinks);
// The same result as scan() into fresh sinks (NearestSet(count, eligible)), sooner on many
// blocks: a pilot scan of every 8th block for the count / 4 nearest gives each sink a bound
// that about 2 count places are expected within, so the full scan keeps only those instead of
// every place closer than the count-th so far; a sink left with fewer than count places
// (a bound too tight) is scanned again without one.
void scan_nearest(const BlockRef* blocks, std::size_t n_blocks, int pairs,
                  const std::uint32_t* queries, int n_queries, std::size_t count, Nearest* sinks);
// out[16 b + l] = squared L2 distance (float, fused multiply-adds in dim order) of lane l of
// block b to query.
void scan_float(const FloatBlockRef* blocks, std::size_t n_blocks, int dims, const float* query,
                float* out);

}  // namespace loopscan::key_scan
