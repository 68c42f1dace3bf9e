#include "loopscan/closure/target_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

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

struct TargetCloud::Index {
  PointsAdaptor adaptor;
  Tree tree;
  explicit Index(const Points3f* points)
      : adaptor{points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(24)) {
    tree.buildIndex();
  }
  // The up to k nearest points within sqrt(bound), nearest first; returns how many. The search
  // starts with the bound as its worst distance, so the tree prunes every branch beyond it.
  std::size_t within(const float* query, std::size_t k, float bound, std::uint32_t* ids,
                     float* d2) const {
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
  fitted_.assign(points_.size(), 0);
  if (!points_.empty()) index_ = std::make_unique<Index>(&points_);
}

// Plane fit over the nearest neighbours within the radius: the normal is the direction of
// least spread, kept only when the spread across is small against the spread along.
void TargetCloud::fit_normal(std::size_t i) const {
  fitted_[i] = 1;
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

bool TargetCloud::has_normal(int i) const {
  const std::size_t k = static_cast<std::size_t>(i);
  if (!fitted_[k]) fit_normal(k);
  return normals_[k].squaredNorm() > 0.5f;
}

const Eigen::Vector3f& TargetCloud::normal(int i) const {
  const std::size_t k = static_cast<std::size_t>(i);
  if (!fitted_[k]) fit_normal(k);
  return normals_[k];
}

TargetCloud::~TargetCloud() = default;
TargetCloud::TargetCloud(TargetCloud&& o) noexcept
    : points_(std::move(o.points_)),
      config_(o.config_),
      normals_(std::move(o.normals_)),
      fitted_(std::move(o.fitted_)),
      index_(std::move(o.index_)) {
  if (index_) index_->adaptor.points = &points_;  // the moved vector keeps its buffer
}
TargetCloud& TargetCloud::operator=(TargetCloud&& o) noexcept {
  points_ = std::move(o.points_);
  config_ = o.config_;
  normals_ = std::move(o.normals_);
  fitted_ = std::move(o.fitted_);
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

PlaceCloud to_place_cloud(const TargetCloud& cloud, std::size_t max_points, double min_vertical) {
  Points3f structure, ground;
  // Classify an even subset of about 1.5 x max_points (each needs a plane fit), then cap.
  const std::size_t stride = std::max<std::size_t>(1, cloud.size() * 2 / (3 * std::max<std::size_t>(max_points, 1)));
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
