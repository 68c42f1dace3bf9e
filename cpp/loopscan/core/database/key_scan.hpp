#pragma once
// Exact k-nearest search over short float keys by one pass over all of them, for several query
// keys at once (a Scan Context query and its lateral versions). Keys are kept in blocks of 16
// places, dimension-major inside a block, so one vector register holds a dimension of 16
// places and the pass costs a few instructions a place per query key, with no pointer chasing.
// For pools of hundreds of neighbours in 10-D this beats a KD-tree at every size measured, up
// to 10^6 places (bench/README.md, "Place database").
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace loopscan {

class KeyScan {
 public:
  static constexpr int kBlock = 16;
  explicit KeyScan(int dims);

  // Appends the key of the next place (dims floats).
  void add(const float* key);
  std::size_t size() const { return count_; }
  int dims() const { return dims_; }

  // For each of the n_queries keys (row-major, dims floats each): up to `count` places with
  // eligible(i), nearest first by distance(), ties to the smaller index. `eligible` is asked
  // only about places closer than the current count-th.
  void nearest(const float* queries, int n_queries, std::size_t count,
               const std::function<bool(std::size_t)>& eligible,
               std::vector<std::vector<std::pair<float, std::size_t>>>& out) const;

  std::size_t memory_bytes() const { return blocks_.capacity() * sizeof(float); }

  // The squared L2 distance the scan computes: per dimension in order, a difference, a
  // product and a sum, no fused multiply-add (every SIMD width gives these bits).
  static float distance(const float* a, const float* b, int dims);

 private:
  int dims_;
  std::size_t count_ = 0;
  std::vector<float> blocks_;  // [block][dim][lane]; unused lanes hold +inf
};

}  // namespace loopscan
