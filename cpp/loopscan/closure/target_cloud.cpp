#include "loopscan/closure/target_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

#include "loopscan/core/parallel.hpp"

namespace loopscan::closure {

struct PointsAdaptor {
  const Points3f* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*points)[i][int(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointsAdaptor>,
                                                 PointsAdaptor, 3, std::uint32_t>;

// Points bucketed in vertical columns of a bird's-eye grid, each column sorted by height: the
// points within a bound of one cell or less lie in the few columns (1-4, at most 9) the
// bound's square touches, within its height range. Most of ICP's searches are like that (the
// last correspondence bounds them, the fine stages' and the score's distances are short), and
// a few array lookups cost a fraction of a tree descent. (Searched for a plane fit's 12
// points, the columns were slower than the tree.)
class ColumnIndex {
 public:
  static constexpr float kCell = 2.0f;  // metres; also the largest bound it answers

  explicit ColumnIndex(const Points3f& points) {
    if (points.empty()) return;
    Eigen::Vector3f lo = points[0], hi = points[0];
    for (const Eigen::Vector3f& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (!(lo.cwiseAbs().maxCoeff() < kReach && hi.cwiseAbs().maxCoeff() < kReach)) return;
    x0_ = lo.x();
    z0_ = lo.z();
    nx_ = column(hi.x(), x0_) + 1;
    nz_ = column(hi.z(), z0_) + 1;
    start_.assign(std::size_t(nx_) * std::size_t(nz_) + 1, 0);
    for (const Eigen::Vector3f& p : points) ++start_[slot(p) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    sorted_.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3f& p = points[i];
      sorted_[fill[slot(p)]++] = Entry{p.x(), p.y(), p.z(), std::uint32_t(i)};
    }
    for (std::size_t c = 0; c + 1 < start_.size(); ++c) {
      std::sort(
          sorted_.begin() + start_[c], sorted_.begin() + start_[c + 1],
          [](const Entry& a, const Entry& b) { return a.y < b.y || (a.y == b.y && a.id < b.id); });
    }
  }

  // How many points (0 or 1) lie within the bound, the nearest in id and d2, for a bound
  // within one cell; -1 otherwise (and for a far cloud or query): the tree answers instead.
  int nearest(const float* q, float bound, std::uint32_t* id, float* d2) const {
    if (start_.empty() || !(bound >= 0 && bound <= kCell * kCell) || !(std::abs(q[0]) < kReach) ||
        !(std::abs(q[1]) < kReach) || !(std::abs(q[2]) < kReach)) {
      return -1;
    }
    // Every point within the bound, with a margin over the float rounding of both sides.
    const float r = std::sqrt(bound) * 1.0001f + 1e-4f;
    const int x_lo = std::max(0, column(q[0] - r, x0_)),
              x_hi = std::min(nx_ - 1, column(q[0] + r, x0_));
    const int z_lo = std::max(0, column(q[2] - r, z0_)),
              z_hi = std::min(nz_ - 1, column(q[2] + r, z0_));
    const float y_lo = q[1] - r, y_hi = q[1] + r;
    float best = std::nextafter(bound, std::numeric_limits<float>::infinity());
    bool any = false;
    for (int x = x_lo; x <= x_hi; ++x) {
      for (int z = z_lo; z <= z_hi; ++z) {
        const std::size_t c = std::size_t(x) * std::size_t(nz_) + std::size_t(z);
        const Entry* e = sorted_.data() + start_[c];
        const Entry* end = sorted_.data() + start_[c + 1];
        while (e != end && e->y < y_lo) ++e;
        for (; e != end && e->y <= y_hi; ++e) {
          // The tree's sum, in its order: the same squared distances to the bit.
          const float dx = q[0] - e->x, dy = q[1] - e->y, dz = q[2] - e->z;
          float d = 0;
          d += dx * dx;
          d += dy * dy;
          d += dz * dz;
          if (d < best || (d == best && any && e->id < *id)) {  // ties: the lower id
            best = d;
            *id = e->id;
            any = true;
          }
        }
      }
    }
    if (any) *d2 = best;
    return any ? 1 : 0;
  }

 private:
  // Metres: float rounding stays under the margin, and the grid under a million columns.
  static constexpr float kReach = 1000.0f;
  struct Entry {
    float x, y, z;
    std::uint32_t id;
  };
  // The floor at and above the origin; below it the truncation, which the clamp to the grid
  // makes the same.
  static int column(float v, float origin) { return int((v - origin) * (1.0f / kCell)); }
  std::size_t slot(const Eigen::Vector3f& p) const {
    return std::size_t(column(p.x(), x0_)) * std::size_t(nz_) + std::size_t(column(p.z(), z0_));
  }

  float x0_ = 0, z0_ = 0;
  int nx_ = 0, nz_ = 0;
  std::vector<std::uint32_t> start_;  // column c holds sorted_[start_[c], start_[c + 1])
  std::vector<Entry> sorted_;
};

struct TargetCloud::Index {
  PointsAdaptor adaptor;
  Tree tree;
  ColumnIndex columns;
  explicit Index(const Points3f* points)
      : adaptor{points},
        tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(24)),
        columns(*points) {
    tree.buildIndex();
  }
  // The up to k nearest points within sqrt(bound), nearest first; returns how many. The
  // columns answer one point within a short bound; the tree, whose search starts with the
  // bound as its worst distance so that it prunes every branch beyond it, the rest.
  std::size_t within(const float* query, std::size_t k, float bound, std::uint32_t* ids,
                     float* d2) const {
    if (k == 1) {
      const int found = columns.nearest(query, bound, ids, d2);
      if (found >= 0) return std::size_t(found);
    }
    nanoflann::KNNResultSet<float, std::uint32_t> result(k);
    result.init(ids, d2);
    d2[k - 1] = std::nextafter(bound, std::numeric_limits<float>::infinity());
    tree.findNeighbors(result, query, nanoflann::SearchParams());
    return result.size();
  }
};

TargetCloud::TargetCloud(Points3f points, const NormalConfig& config)
    : points_(std::move(points)), config_(config) {
  if (config.neighbours < 3 || config.neighbours > 64 || !(config.max_radius_m > 0) ||
      !(config.max_radius_m <= 100) || !(config.max_planarity >= 0 && config.max_planarity <= 1)) {
    throw std::invalid_argument(
        "normal config: neighbours in [3, 64], max_radius_m in (0, 100], max_planarity in [0, 1]");
  }
  for (const Eigen::Vector3f& p : points_) {
    if (!p.allFinite()) throw std::invalid_argument("target cloud: non-finite point");
  }
  normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  state_ = std::make_unique<std::atomic<std::uint8_t>[]>(points_.size());
  if (!points_.empty()) index_ = std::make_unique<Index>(&points_);
}

// Plane fit over the nearest neighbours within the radius: the normal is the direction of
// least spread, kept only when the spread across is small against the spread along.
void TargetCloud::fit_normal(std::size_t i) const {
  const std::size_t k = std::min<std::size_t>(std::size_t(config_.neighbours), points_.size());
  std::uint32_t ids[64];
  float d2[64];
  const std::size_t found = index_->within(
      points_[i].data(), k, static_cast<float>(config_.max_radius_m * config_.max_radius_m), ids, d2);
  if (found < 5) return;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < found; ++j) mean += points_[ids[j]].cast<double>();
  mean /= double(found);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < found; ++j) {
    const Eigen::Vector3d d = points_[ids[j]].cast<double>() - mean;
    scatter += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(scatter);  // closed form, faster than the iterative solver
  const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
  if (!(ev[1] > 0) || ev[0] > config_.max_planarity * ev[1]) return;
  normals_[i] = eig.eigenvectors().col(0).cast<float>().normalized();
}

namespace {
constexpr std::uint8_t kUnfitted = 0, kFitting = 1, kFitted = 2;
}

void TargetCloud::ensure_fitted(std::size_t i) const {
  std::uint8_t s = state_[i].load(std::memory_order_acquire);
  if (s == kFitted) return;
  if (s == kUnfitted && state_[i].compare_exchange_strong(s, kFitting, std::memory_order_acquire)) {
    fit_normal(i);
    state_[i].store(kFitted, std::memory_order_release);
    return;
  }
  // Another thread is fitting it: a plane fit takes microseconds.
  while (state_[i].load(std::memory_order_acquire) != kFitted) std::this_thread::yield();
}

void TargetCloud::fit_normals(int threads, std::size_t stride) const {
  stride = std::max<std::size_t>(stride, 1);
  const std::size_t n = (points_.size() + stride - 1) / stride;
  for_each_index(n, threads, [&](std::size_t k) { ensure_fitted(k * stride); });
}

bool TargetCloud::normal_fitted(int i) const {
  return state_[std::size_t(i)].load(std::memory_order_acquire) == kFitted;
}

bool TargetCloud::has_normal(int i) const {
  const std::size_t k = static_cast<std::size_t>(i);
  ensure_fitted(k);
  return normals_[k].squaredNorm() > 0.5f;
}

const Eigen::Vector3f& TargetCloud::normal(int i) const {
  const std::size_t k = static_cast<std::size_t>(i);
  ensure_fitted(k);
  return normals_[k];
}

TargetCloud::~TargetCloud() = default;
TargetCloud::TargetCloud(TargetCloud&& o) noexcept
    : points_(std::move(o.points_)),
      config_(o.config_),
      normals_(std::move(o.normals_)),
      state_(std::move(o.state_)),
      index_(std::move(o.index_)) {
  if (index_) index_->adaptor.points = &points_;  // the moved vector keeps its buffer
}
TargetCloud& TargetCloud::operator=(TargetCloud&& o) noexcept {
  points_ = std::move(o.points_);
  config_ = o.config_;
  normals_ = std::move(o.normals_);
  state_ = std::move(o.state_);
  index_ = std::move(o.index_);
  if (index_) index_->adaptor.points = &points_;
  return *this;
}

int TargetCloud::nearest(const Eigen::Vector3f& query, float max_squared_distance,
                         float* squared_distance, int hint) const {
  if (points_.empty()) return -1;
  // The bound prunes the tree (most of the work for points without a correspondence). A hint
  // within it lowers it to just above the hint's own distance (the margin covers the tree's
  // summing the squares in another order), so the hint or a nearer point is found.
  float bound = max_squared_distance;
  if (hint >= 0 && std::size_t(hint) < points_.size()) {
    bound = std::min(bound, (points_[std::size_t(hint)] - query).squaredNorm() * (1.0f + 1e-5f) + 1e-30f);
  }
  std::uint32_t id = 0;
  float d2 = 0;
  if (index_->within(query.data(), 1, bound, &id, &d2) == 0) return -1;
  if (squared_distance) *squared_distance = d2;
  return static_cast<int>(id);
}

PlaceCloud to_place_cloud(const TargetCloud& cloud, std::size_t max_points, double min_vertical,
                          int threads) {
  Points3f structure, ground;
  // Classify an even subset of about 1.5 x max_points (each needs a plane fit), then cap.
  const std::size_t stride = std::max<std::size_t>(1, cloud.size() * 2 / (3 * std::max<std::size_t>(max_points, 1)));
  if (threads > 1) cloud.fit_normals(threads, stride);
  for (std::size_t i = 0; i < cloud.size(); i += stride) {
    const bool flat = cloud.has_normal(int(i)) && std::abs(cloud.normal(int(i)).y()) >= min_vertical;
    (flat ? ground : structure).push_back(cloud.points()[i]);
  }
  const std::size_t ground_cap = std::min(ground.size(), max_points / 4);
  const std::size_t structure_cap = std::min(structure.size(), max_points - ground_cap);
  const auto evenly = [](const Points3f& from, std::size_t n, Points3f& to) {
    for (std::size_t i = 0; i < n; ++i) to.push_back(from[i * from.size() / n]);
  };
  PlaceCloud out;
  evenly(structure, structure_cap, out.points);
  out.structure = out.points.size();
  evenly(ground, ground_cap, out.points);
  return out;
}

}  // namespace loopscan::closure
