#pragma once
// The place search of Scan Context's own code, written from its paper (Kim & Kim, IROS 2018)
// as the baseline of the scale benchmark: a KD-tree over the ring key (per ring the mean of
// the structure half over the sectors), the 10 nearest places, each scored by the Scan
// Context distance (1 - mean cosine of the non-empty sector columns) at the best shift, found
// by the sector key (per sector the mean over the rings) and refined within +-10% of the
// sectors around it. Structure half only, as in Scan Context.
#include <cstddef>
#include <memory>
#include <vector>

#include "loopscan/core/signature.hpp"

namespace loopscan::bench {

class ScanContextTree {
 public:
  ScanContextTree(int rings, int sectors);
  ~ScanContextTree();
  void add(const Signature& signature);  // the first row; a tree rebuild is deferred
  void build();                          // (re)builds the tree over every place added
  std::size_t size() const { return count_; }
  // The best place and its distance.
  std::pair<std::size_t, double> query(const Signature& signature, int candidates = 10) const;
  // The same over every place (the tree's oracle).
  std::pair<std::size_t, double> brute_force(const Signature& signature) const;
  std::size_t memory_bytes() const;

 private:
  double distance(const float* q, const float* q_sector_key, std::size_t place) const;
  struct Tree;
  int rings_, sectors_;
  std::size_t count_ = 0;
  std::vector<float> cells_, ring_keys_, sector_keys_;  // per place: R x S, R, S floats
  std::unique_ptr<Tree> tree_;
};

}  // namespace loopscan::bench
