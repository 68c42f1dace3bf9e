#pragma once
// k-nearest search over short keys of 13-bit integers (one per place) for several query keys
// at once (a Scan Context query and its lateral versions), by scanning keys kept in blocks of
// 16 places (key_scan::BlockRef): a few vector instructions per dimension pair and block,
// exact integer distances, no pointer chasing, and a block left as soon as all its places are
// farther than the current k-th (dimensions are stored by decreasing variance, re-laid out
// when the count reaches 256, 1024, 4096, ... up to cells_from, then each time it doubles).
// Up to `cells_from` places every key is scanned: the answer is exact. From there on the keys
// are grouped into cells around k-means centres (trained on the keys when the count reaches
// cells_from, and again at each re-layout from there on, i.e. each time the count doubles;
// about sqrt(n)/2 cells) and a query key scans the cells in the order of its distance to
// their centres until it has seen probe_factor x count keys: an inverted file, whose cost
// stops growing with the map, at the price of rare misses.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace loopscan::key_scan {

constexpr int kBlock = 16;
constexpr std::uint16_t kMaxKey = 8191;  // 64 dims of squared 13-bit differences fit a uint32

// Places: blocks of 16 keys of 13-bit integers, stored in dimension pairs ([pair][lane][2]
// uint16), so one multiply-add of 16-bit lanes squares and sums two dimensions of 16 places.
struct BlockRef {
  const std::uint16_t* keys;  // [pair][lane][2]
  const std::uint32_t* ids;   // [lane]
  std::uint32_t valid;        // lane mask
};
// Cell centres: blocks of float keys ([dim][lane]).
struct FloatBlockRef {
  const float* keys;  // [dim][lane]
  std::uint32_t valid;
};

}  // namespace loopscan::key_scan

namespace loopscan {

struct KeyScanConfig {
  std::size_t cells_from = 32768;
  std::size_t probe_factor = 32;
};

class KeyScan {
 public:
  static constexpr int kBlock = key_scan::kBlock;
  static constexpr std::uint16_t kMaxKey = key_scan::kMaxKey;  // larger values are clamped
  static constexpr int kMaxDims = 64;
  // Throws std::invalid_argument unless 1 <= dims <= kMaxDims.
  explicit KeyScan(int dims, const KeyScanConfig& config = {});
  ~KeyScan();
  KeyScan(const KeyScan&) = delete;
  KeyScan& operator=(const KeyScan&) = delete;

  // Appends the key of the next place (dims values).
  void add(const std::uint16_t* key);
  std::size_t size() const { return count_; }
  int dims() const { return dims_; }
  std::size_t cells() const { return cells_.size(); }

  using Neighbours = std::vector<std::pair<std::uint32_t, std::size_t>>;  // distance, place
  // For each of the n_queries keys (row-major, dims values each): up to `count` places with
  // eligible(i), nearest first by distance(), ties to the smaller index, among the keys
  // scanned (all of them below cells_from). `eligible` is asked only about places within the
  // current bound (the count-th so far, or the pilot scan's: scan_nearest in key_scan.cpp).
  void nearest(const std::uint16_t* queries, int n_queries, std::size_t count,
               const std::function<bool(std::size_t)>& eligible,
               std::vector<Neighbours>& out) const;

  std::size_t memory_bytes() const;

  // The squared L2 distance of two keys (values clamped to kMaxKey), exact.
  static std::uint32_t distance(const std::uint16_t* a, const std::uint16_t* b, int dims);

 private:
  struct Cell {
    std::vector<std::uint32_t> blocks;
    int fill = 0;  // places in the last block
  };
  std::uint16_t* block_keys(std::uint32_t b) const;
  std::uint32_t* block_ids(std::uint32_t b) const;
  key_scan::BlockRef ref(const Cell& cell, std::size_t j) const;
  void place(std::uint32_t cell, const std::uint16_t* key, std::uint32_t id);
  std::uint32_t nearest_cell(const float* key) const;
  void centre_distances(const float* key, float* out) const;
  void set_centres(std::vector<float> centres);
  void lay_out();
  void train(const std::vector<std::uint16_t>& all);

  int dims_, pairs_;
  KeyScanConfig config_;
  std::size_t count_ = 0, next_layout_;  // re-laid out (and, from cells_from, retrained) there
  std::vector<int> order_;               // stored dimension j holds key dimension order_[j]
  // Blocks in chunks (no reallocation of all keys as the map grows).
  std::vector<std::unique_ptr<std::uint16_t[]>> key_chunks_;
  std::vector<std::unique_ptr<std::uint32_t[]>> id_chunks_;
  std::uint32_t n_blocks_ = 0;
  std::vector<Cell> cells_;
  std::vector<float> centres_;      // cells x dims; empty while there is one cell
  std::vector<float> centre_keys_;  // the centres as float blocks
  std::vector<key_scan::FloatBlockRef> centre_refs_;
};

}  // namespace loopscan
