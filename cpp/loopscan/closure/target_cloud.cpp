#include "loopscan/closure/target_cloud.hpp"

#include <cmath>
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
      : adaptor{points}, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {
    tree.buildIndex();
  }
};

TargetCloud::TargetCloud(Points3f points, const NormalConfig& config)
    : points_(std::move(points)) {
  if (config.neighbours < 3 || config.neighbours > 64 || !(config.max_radius_m > 0) ||
      !(config.max_radius_m <= 100) || !(config.max_planarity >= 0 && config.max_planarity <= 1)) {
    throw std::invalid_argument(
        "normal config: neighbours in [3, 64], max_radius_m in (0, 100], max_planarity in [0, 1]");
  }
  for (const Eigen::Vector3f& p : points_) {
    if (!p.allFinite()) throw std::invalid_argument("target cloud: non-finite point");
  }
  normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  if (points_.empty()) return;
  index_ = std::make_unique<Index>(&points_);
  normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  const std::size_t k = std::min<std::size_t>(config.neighbours, points_.size());
  std::vector<std::uint32_t> ids(k);
  std::vector<float> d2(k);
  const float r2 = static_cast<float>(config.max_radius_m * config.max_radius_m);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const std::size_t found = index_->tree.knnSearch(points_[i].data(), k, ids.data(), d2.data());
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::size_t used = 0;
    for (std::size_t j = 0; j < found; ++j) {
      if (d2[j] > r2) continue;
      mean += points_[ids[j]].cast<double>();
      ++used;
    }
    if (used < 5) continue;
    mean /= double(used);
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (std::size_t j = 0; j < found; ++j) {
      if (d2[j] > r2) continue;
      const Eigen::Vector3d d = points_[ids[j]].cast<double>() - mean;
      scatter += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
    if (!(ev[1] > 0) || ev[0] > config.max_planarity * ev[1]) continue;
    normals_[i] = eig.eigenvectors().col(0).cast<float>().normalized();
    ++normal_count_;
  }
}

TargetCloud::~TargetCloud() = default;
TargetCloud::TargetCloud(TargetCloud&& o) noexcept
    : points_(std::move(o.points_)),
      normals_(std::move(o.normals_)),
      index_(std::move(o.index_)),
      normal_count_(o.normal_count_) {
  if (index_) index_->adaptor.points = &points_;  // the moved vector keeps its buffer
}
TargetCloud& TargetCloud::operator=(TargetCloud&& o) noexcept {
  points_ = std::move(o.points_);
  normals_ = std::move(o.normals_);
  index_ = std::move(o.index_);
  normal_count_ = o.normal_count_;
  if (index_) index_->adaptor.points = &points_;
  return *this;
}

int TargetCloud::nearest(const Eigen::Vector3f& query, float max_squared_distance,
                         float* squared_distance) const {
  if (points_.empty()) return -1;
  std::uint32_t id = 0;
  float d2 = 0;
  if (index_->tree.knnSearch(query.data(), 1, &id, &d2) == 0 || d2 > max_squared_distance) {
    return -1;
  }
  if (squared_distance) *squared_distance = d2;
  return static_cast<int>(id);
}

PlaceCloud to_place_cloud(const TargetCloud& cloud, double min_vertical) {
  PlaceCloud out;
  Points3f ground;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const bool flat = cloud.has_normal(int(i)) && std::abs(cloud.normals()[i].y()) >= min_vertical;
    (flat ? ground : out.points).push_back(cloud.points()[i]);
  }
  out.structure = out.points.size();
  out.points.insert(out.points.end(), ground.begin(), ground.end());
  return out;
}

}  // namespace loopscan::closure
