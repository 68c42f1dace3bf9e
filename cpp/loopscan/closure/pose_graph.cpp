#include "loopscan/closure/pose_graph.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <ceres/ceres.h>

namespace loopscan::closure {
namespace detail {

// The parameter blocks and residuals: nodes as position + quaternion, edges as measured
// relative poses with their weights.
constexpr double kPriorSigma = 1e3;  // weak prior of each VO run's first node (m and rad)

struct Node {
  double p[3];
  double q[4];  // x y z w (Eigen's storage order)
};

struct Edge {
  int a = 0, b = 0;
  Eigen::Vector3d p_ab;
  Eigen::Quaterniond q_ab;
  Eigen::Matrix<double, 6, 6> sqrt_info;  // r = sqrt_info * e with r^T r = e^T Sigma^-1 e
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
    Eigen::Matrix<T, 6, 1> raw;
    raw.template head<3>() = p_est - e->p_ab.template cast<T>();
    raw.template tail<3>() = T(2.0) * dq.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> res(r);
    res = e->sqrt_info.template cast<T>() * raw;
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

}  // namespace detail

using namespace detail;

namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

struct PoseGraph::Impl {
  PoseGraphConfig config;
  std::vector<Node> nodes;
  std::vector<Edge> edges;
  std::vector<int> run_starts;  // nodes that begin a VO run (prior, first one fixed)
  std::vector<char> fixed;      // per node: a saved map's place
  bool has_fixed = false;
  int last_movable = -1;  // the node odometry continues from

  double edge_cost(const Edge& e) const {
    double r[6];
    RelativePoseError{&e}(nodes[e.a].p, nodes[e.a].q, nodes[e.b].p, nodes[e.b].q, r);
    double s = 0;
    for (double v : r) s += v * v;
    return s;
  }

  double cost() const {
    double c = 0;
    for (const Edge& e : edges) {
      if (e.active) c += edge_cost(e);
    }
    return 0.5 * c;
  }

  GraphSolve solve() {
    GraphSolve s;
    s.ran = true;
    const auto t0 = std::chrono::steady_clock::now();
    s.cost_before = cost();
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    ceres::EigenQuaternionManifold quaternion;
    for (Node& n : nodes) {
      problem.AddParameterBlock(n.p, 3);
      problem.AddParameterBlock(n.q, 4, &quaternion);
    }
    for (const Edge& e : edges) {
      if (!e.active) continue;
      auto* f = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
          new RelativePoseError{&e});
      problem.AddResidualBlock(f, nullptr, nodes[e.a].p, nodes[e.a].q, nodes[e.b].p,
                               nodes[e.b].q);
    }
    // Later VO runs float: a prior far weaker than any edge (at the current estimate) only
    // fixes their gauge until a loop ties them to the first run.
    for (std::size_t i = has_fixed ? 0 : 1; i < run_starts.size(); ++i) {
      Node& n = nodes[run_starts[i]];
      const Eigen::Isometry3d T = to_pose(n);
      auto* f = new ceres::AutoDiffCostFunction<PriorError, 6, 3, 4>(
          new PriorError{T.translation(), Eigen::Quaterniond(T.rotation())});
      problem.AddResidualBlock(f, nullptr, n.p, n.q);
    }
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (fixed[i] || (i == 0 && !has_fixed)) {
        problem.SetParameterBlockConstant(nodes[i].p);
        problem.SetParameterBlockConstant(nodes[i].q);
      }
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = config.max_iterations;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    s.iterations = static_cast<int>(summary.iterations.size());
    s.cost_after = cost();
    s.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return s;
  }

  // Drops the loop with the largest whitened residual while it is above the limit.
  void drop_disagreeing_loops(GraphSolve& s) {
    for (;;) {
      Edge* worst = nullptr;
      double worst_r = config.max_loop_residual;
      for (Edge& e : edges) {
        if (!e.loop || !e.active) continue;
        const double r = std::sqrt(edge_cost(e));
        if (r > worst_r) worst_r = r, worst = &e;
      }
      if (!worst) return;
      worst->active = false;
      ++s.loops_dropped;
      const GraphSolve again = solve();
      s.iterations += again.iterations;
      s.milliseconds += again.milliseconds;
      s.cost_after = again.cost_after;
    }
  }

  Edge loop_edge(int a, int b, const Eigen::Isometry3d& T_a_b, const Covariance6* covariance) const;

  Edge make_edge(int a, int b, const Eigen::Isometry3d& T_a_b, double sigma_t, double sigma_r,
                 bool loop) const {
    Covariance6 covariance = Covariance6::Zero();
    covariance.diagonal() << Eigen::Vector3d::Constant(sigma_t * sigma_t),
        Eigen::Vector3d::Constant(sigma_r * sigma_r);
    return make_edge(a, b, T_a_b, covariance, loop);
  }

  Edge make_edge(int a, int b, const Eigen::Isometry3d& T_a_b, const Covariance6& covariance,
                 bool loop) const {
    if (a < 0 || b < 0 || a >= int(nodes.size()) || b >= int(nodes.size()) || a == b) {
      throw std::invalid_argument("pose graph: edge between nodes " + std::to_string(a) +
                                  " and " + std::to_string(b) + " of " +
                                  std::to_string(nodes.size()));
    }
    if (!T_a_b.matrix().allFinite()) throw std::invalid_argument("pose graph: non-finite edge");
    Edge e;
    e.a = a, e.b = b, e.loop = loop;
    e.p_ab = T_a_b.translation();
    e.q_ab = Eigen::Quaterniond(T_a_b.rotation()).normalized();
    // Sigma = L L^T, so L^-1 whitens: |L^-1 e|^2 = e^T Sigma^-1 e.
    const Eigen::LLT<Covariance6> llt(covariance);
    if (!covariance.allFinite() || llt.info() != Eigen::Success) {
      throw std::invalid_argument("pose graph: an edge covariance that is not positive definite");
    }
    e.sqrt_info = llt.matrixL().solve(Covariance6::Identity());
    if (!e.sqrt_info.allFinite()) {
      throw std::invalid_argument("pose graph: an edge covariance that is not positive definite");
    }
    return e;
  }
};

void validate(const PoseGraphConfig& c) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(c.odometry_translation_per_m) || !positive(c.odometry_translation_min_m) ||
      !positive(c.odometry_rotation_deg_per_m) || !positive(c.odometry_rotation_min_deg) ||
      !positive(c.loop_translation_m) || !positive(c.loop_rotation_deg) ||
      !positive(c.max_loop_cost) || !positive(c.max_loop_residual) || c.max_iterations < 1 ||
      c.max_iterations > 10000) {
    throw std::invalid_argument(
        "pose graph config: sigmas and limits must be finite and > 0, max_iterations in [1, 10000]");
  }
}

PoseGraph::PoseGraph(const PoseGraphConfig& config) : impl_(std::make_unique<Impl>()) {
  validate(config);
  impl_->config = config;
}
PoseGraph::~PoseGraph() = default;
PoseGraph::PoseGraph(PoseGraph&&) noexcept = default;
PoseGraph& PoseGraph::operator=(PoseGraph&&) noexcept = default;

int PoseGraph::add_node(const Eigen::Isometry3d& initial, const Eigen::Isometry3d* odometry) {
  if (!initial.matrix().allFinite()) throw std::invalid_argument("pose graph: non-finite pose");
  const int id = static_cast<int>(impl_->nodes.size());
  const int previous = impl_->last_movable;
  if (odometry && previous >= 0) {
    // The new node continues the previous one's current estimate, so its edge starts at rest.
    impl_->nodes.push_back(to_node(to_pose(impl_->nodes[std::size_t(previous)]) * (*odometry)));
    const PoseGraphConfig& c = impl_->config;
    const double d = odometry->translation().norm();
    impl_->edges.push_back(impl_->make_edge(
        previous, id, *odometry, std::max(c.odometry_translation_min_m, c.odometry_translation_per_m * d),
        kDeg * std::max(c.odometry_rotation_min_deg, c.odometry_rotation_deg_per_m * d), false));
  } else {
    impl_->nodes.push_back(to_node(initial));
    impl_->run_starts.push_back(id);
  }
  impl_->fixed.push_back(0);
  impl_->last_movable = id;
  return id;
}

int PoseGraph::add_fixed_node(const Eigen::Isometry3d& T_world_cam) {
  if (!T_world_cam.matrix().allFinite()) throw std::invalid_argument("pose graph: non-finite pose");
  impl_->nodes.push_back(to_node(T_world_cam));
  impl_->fixed.push_back(1);
  impl_->has_fixed = true;
  return static_cast<int>(impl_->nodes.size() - 1);
}

void PoseGraph::transform(const Eigen::Isometry3d& T_new_old) {
  for (std::size_t i = 0; i < impl_->nodes.size(); ++i) {
    if (!impl_->fixed[i]) impl_->nodes[i] = to_node(T_new_old * to_pose(impl_->nodes[i]));
  }
}

Edge PoseGraph::Impl::loop_edge(int a, int b, const Eigen::Isometry3d& T_a_b,
                                const Covariance6* covariance) const {
  return covariance ? make_edge(a, b, T_a_b, *covariance, true)
                    : make_edge(a, b, T_a_b, config.loop_translation_m,
                                kDeg * config.loop_rotation_deg, true);
}

int PoseGraph::add_loop_unsolved(int a, int b, const Eigen::Isometry3d& T_a_b,
                                 const Covariance6* covariance) {
  impl_->edges.push_back(impl_->loop_edge(a, b, T_a_b, covariance));
  return static_cast<int>(impl_->edges.size() - 1);
}

double PoseGraph::loop_residual(int a, int b, const Eigen::Isometry3d& T_a_b,
                                const Covariance6* covariance) const {
  return std::sqrt(impl_->edge_cost(impl_->loop_edge(a, b, T_a_b, covariance)));
}

bool PoseGraph::loop_active(int loop_id) const {
  if (loop_id < 0 || std::size_t(loop_id) >= impl_->edges.size()) return false;
  const Edge& e = impl_->edges[std::size_t(loop_id)];
  return e.loop && e.active;
}

GraphSolve PoseGraph::optimise() {
  GraphSolve s = impl_->solve();
  impl_->drop_disagreeing_loops(s);
  return s;
}

bool PoseGraph::add_loop(int a, int b, const Eigen::Isometry3d& T_a_b, GraphSolve* solve,
                         int* loop_id, const Covariance6* covariance) {
  const std::vector<Node> before = impl_->nodes;
  const double cost_before = impl_->cost();
  const int id = add_loop_unsolved(a, b, T_a_b, covariance);
  if (loop_id) *loop_id = id;
  GraphSolve s = impl_->solve();
  bool kept = s.cost_after - cost_before <= impl_->config.max_loop_cost;
  if (!kept) {
    impl_->edges.back().active = false;  // kept inactive, so that ids stay valid
    impl_->nodes = before;
  } else {
    impl_->drop_disagreeing_loops(s);
    kept = impl_->edges.back().active;
  }
  if (solve) *solve = s;
  return kept;
}

std::size_t PoseGraph::size() const { return impl_->nodes.size(); }

Eigen::Isometry3d PoseGraph::pose(int node) const {
  return to_pose(impl_->nodes.at(static_cast<std::size_t>(node)));
}

Eigen::Vector3d PoseGraph::position(int node) const {
  const Node& n = impl_->nodes.at(static_cast<std::size_t>(node));
  return Eigen::Vector3d(n.p[0], n.p[1], n.p[2]);
}

std::size_t PoseGraph::loop_count() const {
  std::size_t n = 0;
  for (const Edge& e : impl_->edges) n += e.loop && e.active;
  return n;
}

std::vector<double> PoseGraph::loop_residuals() const {
  std::vector<double> r;
  for (const Edge& e : impl_->edges) {
    if (e.loop && e.active) r.push_back(std::sqrt(impl_->edge_cost(e)));
  }
  return r;
}

double PoseGraph::cost() const { return impl_->cost(); }

}  // namespace loopscan::closure
