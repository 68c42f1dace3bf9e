#include "loopscan/core/leading_singular.hpp"

#include <Eigen/SVD>
#include <cmath>

namespace loopscan {
namespace {

SingularPair jacobi_pair(const Eigen::MatrixXd& a) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return {svd.matrixU().col(0), svd.matrixV().col(0), svd.singularValues()(0)};
}

void make_sign_canonical(SingularPair& pair) {
  double s = pair.u.sum();
  if (s == 0.0) {
    for (Eigen::Index i = 0; i < pair.u.size() && s == 0.0; ++i) s = pair.u(i);
  }
  if (s < 0.0) {
    pair.u = -pair.u;
    pair.v = -pair.v;
  }
}

}  // namespace

SingularPair leading_singular_pair(const Eigen::MatrixXd& a, Mode mode) {
  if (mode == Mode::Reference) return jacobi_pair(a);
  SingularPair pair{Eigen::VectorXd::Zero(a.rows()), Eigen::VectorXd::Zero(a.cols()), 0.0};
  if (a.size() == 0 || a.cwiseAbs().maxCoeff() == 0.0) return pair;

  // Power iteration on the Gram matrix; for the non-negative M2DP matrices the row sums are an
  // excellent start (Perron vector) and convergence takes a few dozen steps.
  const Eigen::MatrixXd gram = a * a.transpose();
  Eigen::VectorXd u = a.rowwise().sum();
  if (u.norm() == 0.0) u = Eigen::VectorXd::Ones(a.rows());
  u.normalize();
  bool converged = false;
  for (int it = 0; it < 1000 && !converged; ++it) {
    Eigen::VectorXd next = gram * u;
    const double n = next.norm();
    if (n == 0.0) break;
    next /= n;
    if (next.dot(u) < 0) next = -next;
    converged = (next - u).lpNorm<Eigen::Infinity>() < 1e-14;
    u = next;
  }
  if (!converged) {
    pair = jacobi_pair(a);
  } else {
    const Eigen::VectorXd atu = a.transpose() * u;
    pair = {u, atu / atu.norm(), atu.norm()};
  }
  make_sign_canonical(pair);
  return pair;
}

}  // namespace loopscan
