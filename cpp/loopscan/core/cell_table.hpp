#pragma once
// Small open-addressing map from a cell key to the index of the point kept in that cell,
// remembering cells in order of first occurrence. Used by the default-mode filters: it stays
// in cache where std::unordered_map allocates a node per cell.
#include <cstdint>
#include <vector>

namespace loopscan {

class CellTable {
 public:
  void reset(std::size_t expected_cells) {
    std::size_t cap = 16;
    while (cap < 2 * expected_cells) cap <<= 1;
    mask_ = cap - 1;
    keys_.assign(cap, kEmpty);
    slots_.resize(cap);
    order_.clear();
  }
  // Returns the kept point index of `key`, inserting `index` when the cell is new.
  // `inserted` tells which case happened.
  int& find_or_insert(std::int64_t key, int index, bool& inserted) {
    std::size_t h = static_cast<std::size_t>(static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull >> 32) & mask_;
    while (keys_[h] != kEmpty && keys_[h] != key) h = (h + 1) & mask_;
    inserted = keys_[h] == kEmpty;
    if (inserted) {
      keys_[h] = key;
      slots_[h] = static_cast<int>(order_.size());
      order_.push_back(index);
    }
    return order_[slots_[h]];
  }
  // Kept point indices, cells in order of first occurrence.
  const std::vector<int>& kept() const { return order_; }

 private:
  static constexpr std::int64_t kEmpty = INT64_MIN;
  std::size_t mask_ = 0;
  std::vector<std::int64_t> keys_;
  std::vector<int> slots_;
  std::vector<int> order_;
};

}  // namespace loopscan
