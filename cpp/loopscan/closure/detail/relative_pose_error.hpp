// The pose graph's edge residual: a measured relative pose T_a_b against the nodes' poses
// (position + quaternion, x y z w), and the same residual with hand-written Jacobians for the
// solver (automatic differentiation costs about a third of a solve). Not installed (it
// includes Ceres): the library's and the tests' own.
#pragma once

#include <ceres/sized_cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::closure::detail {

// Translation in a's frame, 2 * vector part of the rotation difference; whitened.
struct RelativePoseError {
  const Eigen::Vector3d& p_ab;
  const Eigen::Quaterniond& q_ab;
  const Eigen::Matrix<double, 6, 6>& sqrt_info;

  template <typename T>
  bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* r) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(pa), tb(pb);
    const Eigen::Map<const Eigen::Quaternion<T>> ra(qa), rb(qb);
    const Eigen::Quaternion<T> ra_inv = ra.conjugate();
    const Eigen::Matrix<T, 3, 1> p_est = ra_inv * (tb - ta);
    const Eigen::Quaternion<T> dq = q_ab.template cast<T>().conjugate() * (ra_inv * rb);
    Eigen::Matrix<T, 6, 1> raw;
    raw.template head<3>() = p_est - p_ab.template cast<T>();
    raw.template tail<3>() = T(2.0) * dq.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = sqrt_info.template cast<T>() * raw;
    return true;
  }
};

// p * q = left(p) q = right(q) p, quaternions as (x, y, z, w) vectors.
inline Eigen::Matrix4d left_product(const Eigen::Quaterniond& p) {
  Eigen::Matrix4d m;
  m.topLeftCorner<3, 3>() = p.w() * Eigen::Matrix3d::Identity() + skew(p.vec());
  m.topRightCorner<3, 1>() = p.vec();
  m.bottomLeftCorner<1, 3>() = -p.vec().transpose();
  m(3, 3) = p.w();
  return m;
}

inline Eigen::Matrix4d right_product(const Eigen::Quaterniond& q) {
  Eigen::Matrix4d m;
  m.topLeftCorner<3, 3>() = q.w() * Eigen::Matrix3d::Identity() - skew(q.vec());
  m.topRightCorner<3, 1>() = q.vec();
  m.bottomLeftCorner<1, 3>() = -q.vec().transpose();
  m(3, 3) = q.w();
  return m;
}

// RelativePoseError with its Jacobians in the quaternions' four coordinates, the exact
// derivatives of the formulas it evaluates (Eigen's vector rotation v + w uv + u x uv with
// uv = 2 u x v, and the quaternion products), so they hold off the unit sphere too.
class RelativePoseCost final : public ceres::SizedCostFunction<6, 3, 4, 3, 4> {
 public:
  explicit RelativePoseCost(const RelativePoseError& error) : error_(error) {}

  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    error_(x[0], x[1], x[2], x[3], residuals);
    if (!jacobians) return true;
    const Eigen::Map<const Eigen::Vector3d> ta(x[0]), tb(x[2]);
    const Eigen::Map<const Eigen::Quaterniond> qa(x[1]), qb(x[3]);
    const Eigen::Matrix<double, 6, 6>& S = error_.sqrt_info;
    // p_est = rotate(conj(qa), d): u = -qa.vec, w = qa.w, d = tb - ta.
    const Eigen::Vector3d u = -qa.vec(), d = tb - ta;
    const double w = qa.w();
    const Eigen::Vector3d uv = 2.0 * u.cross(d);
    const Eigen::Matrix3d U = skew(u), D = skew(d);
    const Eigen::Matrix3d dp_dd = Eigen::Matrix3d::Identity() + 2.0 * w * U + 2.0 * U * U;
    const Eigen::Matrix3d dp_du = -2.0 * w * D - skew(uv) - 2.0 * U * D;
    using Block3 = Eigen::Matrix<double, 6, 3, Eigen::RowMajor>;
    using Block4 = Eigen::Matrix<double, 6, 4, Eigen::RowMajor>;
    if (jacobians[0]) Eigen::Map<Block3>{jacobians[0]} = -S.leftCols<3>() * dp_dd;
    if (jacobians[2]) Eigen::Map<Block3>{jacobians[2]} = S.leftCols<3>() * dp_dd;
    const Eigen::Quaterniond m_inv = error_.q_ab.conjugate();
    if (jacobians[1]) {
      Eigen::Matrix<double, 6, 4> raw;
      raw.topLeftCorner<3, 3>() = -dp_du;  // du/d(qa.vec) = -I
      raw.topRightCorner<3, 1>() = uv;     // d p_est / d w
      // dq = m_inv * conj(qa) * qb; conj negates the vector part.
      Eigen::Matrix4d ddq = left_product(m_inv) * right_product(qb);
      ddq.leftCols<3>() *= -1.0;
      raw.bottomRows<3>() = 2.0 * ddq.topRows<3>();
      Eigen::Map<Block4>{jacobians[1]} = S * raw;
    }
    if (jacobians[3]) {
      const Eigen::Quaterniond a = m_inv * qa.conjugate();
      Eigen::Map<Block4>{jacobians[3]} = 2.0 * S.rightCols<3>() * left_product(a).topRows<3>();
    }
    return true;
  }

 private:
  RelativePoseError error_;
};

}  // namespace loopscan::closure::detail
