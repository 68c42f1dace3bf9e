#include "loopscan/core/descriptors/pca_align.hpp"

#include <Eigen/Eigenvalues>

#include <stdexcept>

namespace loopscan {
namespace {

// Every descriptor starts here, so this is where a scan with a NaN, infinite or absurdly large
// coordinate is refused: they make the centroid or the scatter non-finite (one O(1) check
// instead of another pass over the points).
void require_finite(const Eigen::Vector3d& centroid, const Eigen::Matrix3d& scatter) {
  if (!centroid.allFinite() || !scatter.allFinite()) {
    throw std::invalid_argument(
        "describe: the scan has a NaN or infinite coordinate (or one too large to square)");
  }
}

Cloud pca_align_reference(const Cloud& cloud, Eigen::Matrix3d* to_aligned) {
  const Eigen::Index n = static_cast<Eigen::Index>(cloud.size());
  double mx = 0, my = 0, mz = 0;
  for (const PointI& q : cloud) {
    mx += q.p(0);
    my += q.p(1);
    mz += q.p(2);
  }
  mx /= n;
  my /= n;
  mz /= n;
  Eigen::MatrixXd centered(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    centered(i, 0) = cloud[i].p(0) - mx;
    centered(i, 1) = cloud[i].p(1) - my;
    centered(i, 2) = cloud[i].p(2) - mz;
  }
  const Eigen::MatrixXd scatter = centered.transpose() * centered;
  require_finite({mx, my, mz}, scatter);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(scatter);
  if (to_aligned) *to_aligned = solver.eigenvectors().transpose();
  const Eigen::VectorXd a0 = centered * solver.eigenvectors().col(0);
  const Eigen::VectorXd a1 = centered * solver.eigenvectors().col(1);
  const Eigen::VectorXd a2 = centered * solver.eigenvectors().col(2);
  Cloud out(cloud.size());
  for (Eigen::Index i = 0; i < n; ++i) out[i] = {{a0(i), a1(i), a2(i)}, cloud[i].intensity};
  return out;
}

Cloud pca_align_default(const Cloud& cloud, Eigen::Matrix3d* frame) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const PointI& q : cloud) centroid += q.p;
  centroid /= static_cast<double>(cloud.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const PointI& q : cloud) {
    const Eigen::Vector3d d = q.p - centroid;
    scatter.noalias() += d * d.transpose();
  }
  require_finite(centroid, scatter);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Matrix3d basis = solver.eigenvectors();
  if (basis.determinant() < 0) basis.col(0) = -basis.col(0);
  const Eigen::Matrix3d to_aligned = basis.transpose();
  if (frame) *frame = to_aligned;
  Cloud out(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out[i] = {to_aligned * (cloud[i].p - centroid), cloud[i].intensity};
  }
  return out;
}

}  // namespace

Cloud pca_align(const Cloud& cloud, Mode mode, Eigen::Matrix3d* to_aligned) {
  if (to_aligned) to_aligned->setIdentity();
  if (cloud.empty()) return {};
  return mode == Mode::Reference ? pca_align_reference(cloud, to_aligned)
                                 : pca_align_default(cloud, to_aligned);
}

namespace {

// Rows: up = -y, then the camera's x and z (a right-handed basis).
Eigen::Matrix3d camera_axes() {
  Eigen::Matrix3d m;
  m << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  return m;
}

}  // namespace

Cloud align_scan(const Cloud& cloud, DescriptorFrame frame, Mode mode, Eigen::Matrix3d* to_aligned,
                 double lateral_offset_m) {
  Cloud out;
  align_scan(cloud, frame, mode, out, to_aligned, lateral_offset_m);
  return out;
}

void align_scan(const Cloud& cloud, DescriptorFrame frame, Mode mode, Cloud& out,
                Eigen::Matrix3d* to_aligned, double lateral_offset_m) {
  if (mode == Mode::Reference || frame == DescriptorFrame::Pca) {
    out = pca_align(cloud, mode, to_aligned);
    return;
  }
  Eigen::Vector3d centre;
  const Eigen::Matrix3d axes = scan_axes(cloud, frame, &centre, lateral_offset_m);
  if (to_aligned) *to_aligned = axes;
  out.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    out[i] = {axes * (cloud[i].p - centre), cloud[i].intensity};
  }
}

Eigen::Matrix3d scan_axes(const Cloud& cloud, DescriptorFrame frame, Eigen::Vector3d* centre_out,
                          double lateral_offset_m) {
  Eigen::Matrix3d axes = camera_axes();
  *centre_out = Eigen::Vector3d::Zero();
  if (cloud.empty()) return axes;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const PointI& q : cloud) centroid += q.p;
  centroid /= static_cast<double>(cloud.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();  // of (x, z) only: up is given
  if (frame == DescriptorFrame::GravityPca) {
    for (const PointI& q : cloud) {
      const Eigen::Vector3d d(q.p.x() - centroid.x(), 0, q.p.z() - centroid.z());
      scatter.noalias() += d * d.transpose();
    }
  }
  require_finite(centroid, scatter);
  Eigen::Vector3d centre = frame == DescriptorFrame::Camera ? Eigen::Vector3d::Zero() : centroid;
  if (frame == DescriptorFrame::Camera) centre.x() = lateral_offset_m;
  if (frame == DescriptorFrame::Centroid) {
    // The horizontal centroid of the points near the keyframe: the middle of the street
    // whichever lane the car is in (a whole-scan centroid follows the range cut instead).
    constexpr double kDisc = 20.0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double n = 0;
    for (const PointI& q : cloud) {
      if (q.p.x() * q.p.x() + q.p.z() * q.p.z() < kDisc * kDisc) {
        sum += q.p;
        n += 1;
      }
    }
    centre = n > 0 ? Eigen::Vector3d(sum.x() / n, 0, sum.z() / n) : Eigen::Vector3d::Zero();
  }
  if (frame == DescriptorFrame::GravityPca) {
    const Eigen::Matrix2d s2{{scatter(0, 0), scatter(0, 2)}, {scatter(2, 0), scatter(2, 2)}};
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(s2);
    // Horizontal axes by ascending variance like pca_align (the long axis last), right-handed.
    const Eigen::Vector2d u = solver.eigenvectors().col(0), v = solver.eigenvectors().col(1);
    axes.row(1) << u.x(), 0, u.y();
    axes.row(2) << v.x(), 0, v.y();
    if (axes.determinant() < 0) axes.row(1) = -axes.row(1);
  }
  *centre_out = centre;
  return axes;
}

}  // namespace loopscan
