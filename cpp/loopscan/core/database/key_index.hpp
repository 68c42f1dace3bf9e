#pragma once
// A KD-tree (nanoflann) over short keys, one per place, kept contiguous, with exact k-nearest
// search restricted to the places a query may match. Places can be added at any time.
#include <cstddef>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace loopscan {

class KeyIndex {
 public:
  explicit KeyIndex(int dims);
  ~KeyIndex();
  KeyIndex(const KeyIndex&) = delete;
  KeyIndex& operator=(const KeyIndex&) = delete;

  // Appends the key of the next place (dims floats) and indexes it.
  void add(const float* key);
  std::size_t size() const;
  int dims() const;

  // Up to `count` places with eligible(i), nearest to `key` (squared L2), nearest first.
  void nearest(const float* key, std::size_t count,
               const std::function<bool(std::size_t)>& eligible,
               std::vector<std::pair<float, std::size_t>>& out) const;

  std::size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loopscan
