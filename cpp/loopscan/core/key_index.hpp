#pragma once
// A KD-tree over short keys read in place from the database's payloads (nanoflann's dynamic
// forest, so adding a place never rebuilds the whole tree), with k-nearest search restricted
// to the places a query may match.
#include <cstddef>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "loopscan/core/payload_arena.hpp"

namespace loopscan {

// Key d of place i is arena.at(i)[offset + d * step].
struct KeyLayout {
  int dims = 0;
  std::size_t offset = 0, step = 1;
};

class KeyIndex {
 public:
  KeyIndex(const KeyLayout& layout, const PayloadArena* data);
  ~KeyIndex();
  KeyIndex(const KeyIndex&) = delete;
  KeyIndex& operator=(const KeyIndex&) = delete;

  // Indexes places [indexed(), n).
  void extend(std::size_t n);
  std::size_t indexed() const;

  // Up to `count` places with eligible(i), nearest to `key` (squared L2), nearest first.
  void nearest(const float* key, std::size_t count, const std::function<bool(std::size_t)>& eligible,
               std::vector<std::pair<float, std::size_t>>& out) const;

  std::size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loopscan
