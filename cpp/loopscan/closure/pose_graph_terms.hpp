#pragma once
// The pose graph's parameter blocks and residuals (namespace detail, shared by pose_graph.cpp
// only): nodes as position + quaternion, edges as measured relative poses with their weights.
#include <Eigen/Geometry>

namespace loopscan::closure::detail {

constexpr double kPriorSigma = 1e3;  // weak prior of each VO run's first node (m and rad)

struct Node {
  double p[3];
  double q[4];  // x y z w (Eigen's storage order)
};

struct Edge {
  int a = 0, b = 0;
  Eigen::Vector3d p_ab;
  Eigen::Quaterniond q_ab;
  Eigen::Matrix<double, 6, 1> sqrt_info;
  bool loop = false;
  bool active = true;
};

// Residual of T_a_b against its measurement: translation in a's frame, 2 * vector part of the
// rotation difference; whitened.
struct RelativePoseError {
  const Edge* e;
  template <typename T>
  bool operator()(const T* pa, const T* qa, const T* pb, const T* qb, T* r) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> ta(pa), tb(pb);
    const Eigen::Map<const Eigen::Quaternion<T>> ra(qa), rb(qb);
    const Eigen::Quaternion<T> ra_inv = ra.conjugate();
    const Eigen::Matrix<T, 3, 1> p_est = ra_inv * (tb - ta);
    const Eigen::Quaternion<T> dq = e->q_ab.template cast<T>().conjugate() * (ra_inv * rb);
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res.template head<3>() = p_est - e->p_ab.template cast<T>();
    res.template tail<3>() = T(2.0) * dq.vec();
    for (int k = 0; k < 6; ++k) res[k] *= T(e->sqrt_info[k]);
    return true;
  }
};

struct PriorError {
  Eigen::Vector3d p0;
  Eigen::Quaterniond q0;
  template <typename T>
  bool operator()(const T* p, const T* q, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rq(q);
    const Eigen::Quaternion<T> dq = q0.template cast<T>().conjugate() * rq;
    for (int k = 0; k < 3; ++k) r[k] = (p[k] - T(p0[k])) / T(kPriorSigma);
    for (int k = 0; k < 3; ++k) r[3 + k] = T(2.0) * dq.vec()[k] / T(kPriorSigma);
    return true;
  }
};

inline Eigen::Isometry3d to_pose(const Node& n) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(n.q[3], n.q[0], n.q[1], n.q[2]).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(n.p[0], n.p[1], n.p[2]);
  return T;
}

inline Node to_node(const Eigen::Isometry3d& T) {
  Node n;
  const Eigen::Quaterniond q(T.rotation());
  for (int k = 0; k < 3; ++k) n.p[k] = T.translation()[k];
  n.q[0] = q.x(), n.q[1] = q.y(), n.q[2] = q.z(), n.q[3] = q.w();
  return n;
}

}  // namespace loopscan::closure::detail
