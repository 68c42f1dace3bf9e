// The centreline's box tree: which segments come within a radius of a point, for the
// renderer's ground caches (render_ground.hpp). Far from the streets a radius holds few
// segments but many grid cells; the tree visits only the boxes the search ring meets.
#include <algorithm>
#include <cmath>

#include "loopscan/sim/world_centreline.hpp"

namespace loopscan::sim {

void CentrelineIndex::build_tree() {
  const auto n = static_cast<std::uint32_t>(segs_.size());
  const std::uint32_t leaves = (n + kLeaf - 1) / kLeaf;
  leaf_base_ = 1;
  while (leaf_base_ < leaves) leaf_base_ *= 2;
  tree_segs_.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) tree_segs_[s] = s;
  split_tree(1, 0, leaf_base_);
  constexpr double inf = std::numeric_limits<double>::infinity();
  tree_.assign(2 * static_cast<std::size_t>(leaf_base_), TreeBox{inf, inf, -inf, -inf});
  for (std::uint32_t k = 0; k < n; ++k) {
    TreeBox& b = tree_[leaf_base_ + k / kLeaf];
    const Segment& g = segs_[tree_segs_[k]];
    b = {std::min({b.x0, g.ax, g.bx}), std::min({b.z0, g.az, g.bz}), std::max({b.x1, g.ax, g.bx}),
         std::max({b.z1, g.az, g.bz})};
  }
  for (std::uint32_t i = leaf_base_ - 1; i >= 1; --i) {
    const TreeBox &a = tree_[2 * i], &b = tree_[2 * i + 1];
    tree_[i] = {std::min(a.x0, b.x0), std::min(a.z0, b.z0), std::max(a.x1, b.x1),
                std::max(a.z1, b.z1)};
  }
}

// Orders tree_segs_ of the node's leaves so that each half of them lies on one side of the
// median midpoint along the longer side of their extent.
void CentrelineIndex::split_tree(std::uint32_t node, std::uint32_t first_leaf,
                                 std::uint32_t leaves) {
  const auto n = static_cast<std::uint32_t>(tree_segs_.size());
  const std::uint32_t lo = std::min(first_leaf * kLeaf, n),
                      hi = std::min((first_leaf + leaves) * kLeaf, n);
  if (leaves <= 1 || hi - lo <= kLeaf) return;
  const auto mid_x = [&](std::uint32_t s) { return segs_[s].ax + segs_[s].bx; };
  const auto mid_z = [&](std::uint32_t s) { return segs_[s].az + segs_[s].bz; };
  double x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300;
  for (std::uint32_t k = lo; k < hi; ++k) {
    x0 = std::min(x0, mid_x(tree_segs_[k]));
    x1 = std::max(x1, mid_x(tree_segs_[k]));
    z0 = std::min(z0, mid_z(tree_segs_[k]));
    z1 = std::max(z1, mid_z(tree_segs_[k]));
  }
  const std::uint32_t half = leaves / 2, mid = std::min((first_leaf + half) * kLeaf, n);
  const bool along_x = x1 - x0 >= z1 - z0;
  // Ties by index: the order, and so the tree, does not depend on the library's nth_element.
  std::nth_element(tree_segs_.begin() + lo, tree_segs_.begin() + mid, tree_segs_.begin() + hi,
                   [&](std::uint32_t a, std::uint32_t b) {
                     const double ka = along_x ? mid_x(a) : mid_z(a);
                     const double kb = along_x ? mid_x(b) : mid_z(b);
                     return ka != kb ? ka < kb : a < b;
                   });
  split_tree(2 * node, first_leaf, half);
  split_tree(2 * node + 1, first_leaf + half, leaves - half);
}

void CentrelineIndex::segments_within(double x, double z, double empty, double radius,
                                      std::vector<Candidate>& out) const {
  out.clear();
  if (segs_.empty()) return;
  const double r2 = radius * radius, e2 = empty > 0.0 ? empty * empty : -1.0;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 1;
  while (top > 0) {
    const std::uint32_t i = stack[--top];
    const TreeBox& b = tree_[i];
    // Skip boxes wholly outside the radius or wholly inside the empty disc.
    const double nx = std::max({b.x0 - x, x - b.x1, 0.0}), nz = std::max({b.z0 - z, z - b.z1, 0.0});
    if (nx * nx + nz * nz > r2) continue;
    const double fx = std::max(x - b.x0, b.x1 - x), fz = std::max(z - b.z0, b.z1 - z);
    if (fx * fx + fz * fz < e2) continue;
    if (i < leaf_base_) {
      stack[top++] = 2 * i + 1;
      stack[top++] = 2 * i;
      continue;
    }
    const std::uint32_t s0 = (i - leaf_base_) * kLeaf;
    const auto s1 = std::min<std::uint32_t>(s0 + kLeaf, static_cast<std::uint32_t>(segs_.size()));
    for (std::uint32_t k = s0; k < s1; ++k) {
      double t;
      const double d = std::sqrt(distance2(segs_[tree_segs_[k]], x, z, t));
      if (d <= radius) out.push_back({d, tree_segs_[k]});
    }
  }
  std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.segment < b.segment;
  });
}

CentrelineIndex::Nearest CentrelineIndex::nearest_from(std::uint32_t hint, double x,
                                                       double z) const {
  Nearest best;
  if (segs_.empty()) return best;
  hint = std::min<std::uint32_t>(hint, static_cast<std::uint32_t>(segs_.size()) - 1);
  double t_best;
  double best2 = distance2(segs_[hint], x, z, t_best);
  std::uint32_t best_s = hint;
  const auto box_distance2 = [&](const TreeBox& b) {
    const double nx = b.x0 > x ? b.x0 - x : (x > b.x1 ? x - b.x1 : 0.0);
    const double nz = b.z0 > z ? b.z0 - z : (z > b.z1 ? z - b.z1 : 0.0);
    return nx * nx + nz * nz;
  };
  struct Entry {
    std::uint32_t node;
    double d2;  // box distance, squared
  };
  Entry stack[64];
  int top = 0;
  stack[top++] = {1, box_distance2(tree_[1])};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 > best2) continue;  // equal: may hold a tie of lower index
    const std::uint32_t i = e.node;
    if (i < leaf_base_) {  // the nearer child first
      const double l = box_distance2(tree_[2 * i]), r = box_distance2(tree_[2 * i + 1]);
      if (l <= r) {
        if (r <= best2) stack[top++] = {2 * i + 1, r};
        if (l <= best2) stack[top++] = {2 * i, l};
      } else {
        if (l <= best2) stack[top++] = {2 * i, l};
        if (r <= best2) stack[top++] = {2 * i + 1, r};
      }
      continue;
    }
    const std::uint32_t s0 = (i - leaf_base_) * kLeaf;
    const auto s1 = std::min<std::uint32_t>(s0 + kLeaf, static_cast<std::uint32_t>(segs_.size()));
    for (std::uint32_t k = s0; k < s1; ++k) {
      const std::uint32_t s = tree_segs_[k];
      double t;
      const double d2 = distance2(segs_[s], x, z, t);
      if (d2 < best2 || (d2 == best2 && s < best_s)) {
        best2 = d2;
        best_s = s;
        t_best = t;
      }
    }
  }
  const Segment& g = segs_[best_s];
  best.distance = std::sqrt(best2);
  best.y = g.ay + t_best * (g.by - g.ay);
  best.found = true;
  best.segment = best_s;
  return best;
}

}  // namespace loopscan::sim
