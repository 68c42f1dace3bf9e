#include "loopscan/closure/pose_graph.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <ceres/ceres.h>

#include "loopscan/closure/detail/relative_pose_error.hpp"
#include "loopscan/core/rigid_motion.hpp"

namespace loopscan::closure {
namespace detail {

// The parameter blocks and residuals: nodes as position + quaternion, edges as measured
// relative poses with their weights.
constexpr double kPriorSigma = 1e3;  // weak prior of each VO run's first node (m and rad)
// A coarse solve stops earlier than an exact one: its answer is an approximation anyway.
constexpr double kCoarseTolerance = 1e-4;

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
  bool absorbed = false;  // inactive because a merge took it over (a loop: kept for good)
};

// A relative pose with its covariance, perturbed as the residual is: translation additive in
// the first node's frame, rotation on the right.
struct Measurement {
  Eigen::Isometry3d T;
  Covariance6 C;
};

inline Measurement measurement(const Edge& e) {
  Measurement m;
  m.T = Eigen::Isometry3d::Identity();
  m.T.linear() = e.q_ab.toRotationMatrix();
  m.T.translation() = e.p_ab;
  const Covariance6 L = e.sqrt_info.inverse();  // sqrt_info = L^-1 with Sigma = L L^T
  m.C = L * L.transpose();
  return m;
}

inline Measurement inverse(const Measurement& m) {
  const Eigen::Matrix3d R = m.T.rotation();
  Covariance6 J = Covariance6::Zero();
  J.topLeftCorner<3, 3>() = -R.transpose();
  J.topRightCorner<3, 3>() = -skew(R.transpose() * m.T.translation());
  J.bottomRightCorner<3, 3>() = -R;
  return {m.T.inverse(), J * m.C * J.transpose()};
}

// T_a_c = T_a_b * T_b_c with T_b_c exact.
inline Measurement compose(const Measurement& ab, const Eigen::Isometry3d& T_bc) {
  Covariance6 J = Covariance6::Identity();
  J.topRightCorner<3, 3>() = -ab.T.rotation() * skew(T_bc.translation());
  J.bottomRightCorner<3, 3>() = T_bc.rotation().transpose();
  return {ab.T * T_bc, J * ab.C * J.transpose()};
}

// T_a_c = T_a_b * T_b_c with T_a_b exact.
inline Measurement compose(const Eigen::Isometry3d& T_ab, const Measurement& bc) {
  Covariance6 J = Covariance6::Identity();
  J.topLeftCorner<3, 3>() = T_ab.rotation();
  return {T_ab * bc.T, J * bc.C * J.transpose()};
}

// T_a_c = T_a_b * T_b_c, both measured independently.
inline Measurement compose(const Measurement& ab, const Measurement& bc) {
  Measurement ac = compose(ab, bc.T);
  ac.C += compose(ab.T, bc).C;
  return ac;
}

// The estimate two independent measurements of one relative pose give together: the minimum
// of both residuals' costs, linearised at the first.
inline Measurement fuse(const Measurement& m1, const Measurement& m2) {
  const Covariance6 I1 = m1.C.inverse(), I2 = m2.C.inverse();
  const Covariance6 C = (I1 + I2).inverse();
  const Eigen::Quaterniond q1(m1.T.rotation());
  Eigen::Quaterniond dq = q1.conjugate() * Eigen::Quaterniond(m2.T.rotation());
  if (dq.w() < 0) dq.coeffs() *= -1;
  Eigen::Matrix<double, 6, 1> d;
  d << m2.T.translation() - m1.T.translation(), 2.0 * dq.vec();
  const Eigen::Matrix<double, 6, 1> step = C * (I2 * d);
  const Eigen::Vector3d half = 0.5 * step.tail<3>();
  const Eigen::Quaterniond turn(std::sqrt(std::max(0.0, 1.0 - half.squaredNorm())), half.x(),
                                half.y(), half.z());
  Measurement out;
  out.T = Eigen::Isometry3d::Identity();
  out.T.linear() = (q1 * turn).normalized().toRotationMatrix();
  out.T.translation() = m1.T.translation() + step.head<3>();
  out.C = 0.5 * (C + C.transpose());
  return out;
}

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
  std::vector<std::vector<int>> node_edges;  // per node: its edges
  std::vector<int> run_starts;  // nodes that begin a VO run (prior, first one fixed)
  std::vector<char> fixed;      // per node: a saved map's place
  std::vector<int> merged_into;  // per node: -1, or the node it follows (its pose there in nodes)
  std::size_t merged_count = 0;

  std::size_t solved_nodes() const { return nodes.size() - merged_count; }
  bool has_fixed = false;
  int last_movable = -1;  // the node odometry continues from
  std::vector<int> changed;  // nodes added or given an edge since the last solve
  bool approximate = false;  // a local solve ran since the last whole-graph one

  int add_node(const Node& n, bool is_fixed) {
    nodes.push_back(n);
    node_edges.emplace_back();
    fixed.push_back(is_fixed ? 1 : 0);
    merged_into.push_back(-1);
    const int id = static_cast<int>(nodes.size() - 1);
    changed.push_back(id);
    return id;
  }

  int add_edge(const Edge& e) {
    const int id = static_cast<int>(edges.size());
    edges.push_back(e);
    node_edges[std::size_t(e.a)].push_back(id);
    node_edges[std::size_t(e.b)].push_back(id);
    changed.push_back(e.a);
    changed.push_back(e.b);
    return id;
  }

  Eigen::Matrix<double, 6, 1> residual(const Edge& e) const {
    Eigen::Matrix<double, 6, 1> r;
    RelativePoseError{e.p_ab, e.q_ab, e.sqrt_info}(
        nodes[std::size_t(e.a)].p, nodes[std::size_t(e.a)].q, nodes[std::size_t(e.b)].p,
        nodes[std::size_t(e.b)].q, r.data());
    return r;
  }

  double edge_cost(const Edge& e) const { return residual(e).squaredNorm(); }

  double cost() const {
    double c = 0;
    for (const Edge& e : edges) {
      if (e.active) c += edge_cost(e);
    }
    return 0.5 * c;
  }

  // Nodes no solve moves: a saved map's places, and the first node when there is no map.
  bool held(std::size_t i) const { return fixed[i] || (i == 0 && !has_fixed); }

  // Solves for the nodes marked in `inside` (nullptr: every node); the other ends of edges
  // leaving the window hold still. Costs are of the edges the solve can change.
  GraphSolve solve(const std::vector<char>* inside, double function_tolerance = 1e-6) {
    GraphSolve s;
    s.ran = true;
    const auto t0 = std::chrono::steady_clock::now();
    const auto moves = [&](int i) { return !inside || (*inside)[std::size_t(i)]; };
    std::vector<const Edge*> touched;
    for (const Edge& e : edges) {
      if (e.active && (moves(e.a) || moves(e.b))) touched.push_back(&e);
    }
    const auto touched_cost = [&] {
      double c = 0;
      for (const Edge* e : touched) c += edge_cost(*e);
      return 0.5 * c;
    };
    s.cost_before = touched_cost();
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    ceres::EigenQuaternionManifold quaternion;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (!moves(int(i)) || merged_into[i] >= 0) continue;
      Node& n = nodes[i];
      problem.AddParameterBlock(n.p, 3);
      problem.AddParameterBlock(n.q, 4, &quaternion);
      if (held(i)) {
        problem.SetParameterBlockConstant(n.p);
        problem.SetParameterBlockConstant(n.q);
      }
    }
    for (const Edge* e : touched) {
      for (const int end : {e->a, e->b}) {
        if (moves(end)) continue;
        Node& n = nodes[std::size_t(end)];
        problem.AddParameterBlock(n.p, 3);
        problem.AddParameterBlock(n.q, 4);
        problem.SetParameterBlockConstant(n.p);
        problem.SetParameterBlockConstant(n.q);
      }
      auto* f = new RelativePoseCost({e->p_ab, e->q_ab, e->sqrt_info});
      problem.AddResidualBlock(f, nullptr, nodes[std::size_t(e->a)].p, nodes[std::size_t(e->a)].q,
                               nodes[std::size_t(e->b)].p, nodes[std::size_t(e->b)].q);
    }
    // Later VO runs float: a prior far weaker than any edge (at the current estimate) only
    // fixes their gauge until a loop ties them to the first run.
    for (std::size_t i = has_fixed ? 0 : 1; i < run_starts.size(); ++i) {
      if (!moves(run_starts[i]) || merged_into[std::size_t(run_starts[i])] >= 0) continue;
      Node& n = nodes[std::size_t(run_starts[i])];
      const Eigen::Isometry3d T = to_pose(n);
      auto* f = new ceres::AutoDiffCostFunction<PriorError, 6, 3, 4>(
          new PriorError{T.translation(), Eigen::Quaterniond(T.rotation())});
      problem.AddResidualBlock(f, nullptr, n.p, n.q);
    }
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = config.max_iterations;
    options.function_tolerance = function_tolerance;
    options.num_threads = 1;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    s.iterations = static_cast<int>(summary.iterations.size());
    s.cost_after = touched_cost();
    s.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return s;
  }

  GraphSolve solve_whole() {
    GraphSolve s = solve(nullptr);
    s.whole_graph = true;
    s.moved_nodes = solved_nodes();
    changed.clear();
    approximate = false;
    return s;
  }

  // The whole graph solved through a coarse one (see PoseGraphConfig::coarse_nodes): its
  // nodes are the ends of odometry chains (nodes with a prior, a held pose or other than two
  // odometry edges) and evenly spaced nodes along each chain; its edges the chains'
  // measurements composed, and the loops moved to these nodes. The nodes between are placed
  // from their chain's measurements. Costs are the fine graph's. `changed` stays: the caller
  // refines around it.
  GraphSolve solve_coarse() {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t n = nodes.size();
    std::vector<char> starts_run(n, 0);
    for (const int r : run_starts) starts_run[std::size_t(r)] = 1;
    const auto other_end = [&](const Edge& e, int from) { return e.a == from ? e.b : e.a; };
    // Interior: exactly two active odometry edges to two different nodes (and any loops),
    // no prior, not held.
    const auto chain_edge = [&](int id) {
      const Edge& e = edges[std::size_t(id)];
      return e.active && !e.loop;
    };
    std::vector<char> key(n, 0);  // (merged nodes are neither key nor interior)
    for (std::size_t i = 0; i < n; ++i) {
      if (merged_into[i] >= 0) continue;
      int ends[3], count = 0;
      for (const int id : node_edges[i]) {
        if (chain_edge(id) && count < 3) ends[count++] = other_end(edges[std::size_t(id)], int(i));
      }
      key[i] = held(i) || starts_run[i] || count != 2 || ends[0] == ends[1];
    }
    const auto next_edge = [&](int node, int came_by) {
      for (const int id : node_edges[std::size_t(node)]) {
        if (id != came_by && chain_edge(id)) return id;
      }
      return -1;
    };
    // The interior nodes from `k` along edge `id`, then the next key node.
    const auto walk = [&](int k, int id, std::vector<std::pair<int, int>>& steps) {
      steps.clear();
      int at = k;
      for (;;) {
        const int to = other_end(edges[std::size_t(id)], at);
        steps.emplace_back(to, id);
        if (key[std::size_t(to)]) return;
        at = to;
        id = next_edge(at, id);
      }
    };
    const std::size_t stride =
        std::max<std::size_t>(2, (solved_nodes() + std::size_t(config.coarse_nodes) - 1) /
                                     std::size_t(config.coarse_nodes));
    std::vector<std::pair<int, int>> steps;  // (node reached, edge taken)
    std::vector<char> visited(n, 0);
    const auto mark_stride = [&](int k) {
      for (const int id : node_edges[std::size_t(k)]) {
        const int first = other_end(edges[std::size_t(id)], k);
        if (!chain_edge(id) || key[std::size_t(first)] || visited[std::size_t(first)]) continue;
        walk(k, id, steps);
        for (std::size_t s = 0; s + 1 < steps.size(); ++s) {
          visited[std::size_t(steps[s].first)] = 1;
          if ((s + 1) % stride == 0) key[std::size_t(steps[s].first)] = 1;
        }
        // A chain back to where it began needs a node of its own between.
        if (steps.back().first == k && steps.size() > 1) {
          key[std::size_t(steps[(steps.size() - 1) / 2].first)] = 1;
        }
      }
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (key[i]) mark_stride(int(i));
    }
    for (std::size_t i = 0; i < n; ++i) {  // rings of interior nodes only
      if (merged_into[i] < 0 && !key[i] && !visited[i]) key[i] = 1, mark_stride(int(i));
    }

    Impl coarse;
    coarse.config = config;
    coarse.has_fixed = true;  // every held node is marked fixed below
    std::vector<int> index(n, -1);
    std::vector<int> key_nodes;
    for (std::size_t i = 0; i < n; ++i) {
      if (!key[i]) continue;
      index[i] = coarse.add_node(nodes[i], held(i));
      key_nodes.push_back(int(i));
    }
    for (std::size_t r = has_fixed ? 0 : 1; r < run_starts.size(); ++r) {
      const int at = index[std::size_t(run_starts[r])];
      if (at >= 0) coarse.run_starts.push_back(at);  // (-1: merged)
    }
    // A chain's nodes are placed from its measurements (not their current, possibly strained,
    // estimates): each node's pose from either end, blended by the covariance up to it.
    struct Inner {
      int node;
      double up_to;              // covariance trace from the chain's start
      Eigen::Isometry3d T_from;  // measured pose in the start's frame
    };
    struct Chain {
      int from, to;
      Eigen::Isometry3d T_from_to;
      double total = 0;
      std::vector<Inner> inner;
    };
    std::vector<Chain> chains;
    // per interior node: the chain end its loops attach to, and its measured pose there
    std::vector<std::pair<int, Eigen::Isometry3d>> anchor(n, {-1, Eigen::Isometry3d::Identity()});
    std::vector<char> used(edges.size(), 0);
    for (const int k : key_nodes) {
      for (const int id : node_edges[std::size_t(k)]) {
        if (used[std::size_t(id)] || !chain_edge(id)) continue;
        walk(k, id, steps);
        Chain c{k, steps.back().first, Eigen::Isometry3d::Identity(), 0, {}};
        Measurement m;
        int at = k;
        for (std::size_t s = 0; s < steps.size(); ++s) {
          const Edge& e = edges[std::size_t(steps[s].second)];
          used[std::size_t(steps[s].second)] = 1;
          const Measurement step = e.a == at ? measurement(e) : inverse(measurement(e));
          m = s == 0 ? step : compose(m, step);
          c.total += step.C.topLeftCorner<3, 3>().trace();
          if (s + 1 < steps.size()) c.inner.push_back({steps[s].first, c.total, m.T});
          at = steps[s].first;
        }
        c.T_from_to = m.T;
        coarse.add_edge(coarse.make_edge(index[std::size_t(c.from)], index[std::size_t(c.to)], m.T,
                                         m.C, false));
        for (const Inner& i : c.inner) {
          anchor[std::size_t(i.node)] =
              2 * i.up_to < c.total ? std::make_pair(c.from, i.T_from)
                                    : std::make_pair(c.to, c.T_from_to.inverse() * i.T_from);
        }
        if (!c.inner.empty()) chains.push_back(std::move(c));
      }
    }
    // Loops move to the anchors of their ends, composed with the chains' measurements (exact
    // over a few nodes); a loop within one chain part says nothing at this scale.
    const auto moved_end = [&](int node) {
      return anchor[std::size_t(node)].first >= 0
                 ? anchor[std::size_t(node)]
                 : std::make_pair(node, Eigen::Isometry3d(Eigen::Isometry3d::Identity()));
    };
    // Loops that land on the same two nodes are fused into one edge (fewer residuals, the
    // same information).
    std::map<std::pair<int, int>, Measurement> loops;
    for (const Edge& e : edges) {
      if (!e.active || !e.loop) continue;
      auto [a, T_a_ea] = moved_end(e.a);
      auto [b, T_b_eb] = moved_end(e.b);
      if (a == b) continue;
      Measurement m = compose(compose(T_a_ea, measurement(e)), T_b_eb.inverse());
      if (a > b) std::swap(a, b), m = inverse(m);
      const auto [at, added] = loops.try_emplace({a, b}, m);
      if (!added) at->second = fuse(at->second, m);
    }
    for (const auto& [ends, m] : loops) {
      coarse.add_edge(coarse.make_edge(index[std::size_t(ends.first)],
                                       index[std::size_t(ends.second)], m.T, m.C, true));
    }

    GraphSolve s;
    s.cost_before = cost();
    const GraphSolve inner = coarse.solve(nullptr, kCoarseTolerance);
    s.ran = true;
    s.coarse = true;
    s.iterations = inner.iterations;
    for (std::size_t j = 0; j < key_nodes.size(); ++j) {
      nodes[std::size_t(key_nodes[j])] = coarse.nodes[j];
    }
    for (const Chain& c : chains) {
      const Eigen::Isometry3d A = to_pose(nodes[std::size_t(c.from)]);
      const Eigen::Isometry3d B = to_pose(nodes[std::size_t(c.to)]) * c.T_from_to.inverse();
      const Eigen::Quaterniond qa(A.rotation()), qb(B.rotation());
      for (const Inner& i : c.inner) {
        const double f = c.total > 0 ? i.up_to / c.total : 0.5;
        Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
        out.linear() =
            (qa.slerp(f, qb) * Eigen::Quaterniond(i.T_from.rotation())).toRotationMatrix();
        out.translation() =
            (1 - f) * (A * i.T_from.translation()) + f * (B * i.T_from.translation());
        nodes[std::size_t(i.node)] = to_node(out);
      }
    }
    s.cost_after = cost();
    s.moved_nodes = solved_nodes();
    s.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    approximate = true;
    return s;
  }

  // Solves every node: exactly, or through the coarse graph once it is larger than a
  // window may grow.
  GraphSolve solve_all() {
    return config.coarse_nodes > 0 && solved_nodes() > std::size_t(config.coarse_above_nodes)
               ? solve_coarse()
               : solve_whole();
  }

  // The nodes within the fewest edges of `changed`, whole layers of a breadth-first search
  // until there are at least `count`.
  std::vector<char> window(std::size_t count, std::size_t& size) const {
    std::vector<char> inside(nodes.size(), 0);
    std::vector<int> layer, next;
    for (const int n : changed) {
      if (!inside[std::size_t(n)]) inside[std::size_t(n)] = 1, layer.push_back(n);
    }
    size = layer.size();
    while (size < count && !layer.empty()) {
      next.clear();
      for (const int n : layer) {
        if (held(std::size_t(n))) continue;  // nodes joined only through it do not interact
        for (const int id : node_edges[std::size_t(n)]) {
          const Edge& e = edges[std::size_t(id)];
          const int other = e.a == n ? e.b : e.a;
          if (e.active && !inside[std::size_t(other)]) {
            inside[std::size_t(other)] = 1;
            next.push_back(other);
          }
        }
      }
      size += next.size();
      layer.swap(next);
    }
    return inside;
  }

  // Solves around `changed` (see PoseGraphConfig::window_nodes). The costs are those of the
  // edges the largest window touched.
  GraphSolve solve_changed() {
    // (nodes merged since they changed have no edges left to solve)
    changed.erase(std::remove_if(changed.begin(), changed.end(),
                                 [&](int n) { return merged_into[std::size_t(n)] >= 0; }),
                  changed.end());
    if (changed.empty()) return {};
    if (!config.incremental) return solve_whole();
    GraphSolve total;
    total.ran = true;
    double earlier_change = 0;  // cost change of the smaller windows, all inside the larger
    const auto add = [&](const GraphSolve& s, std::size_t moved) {
      total.iterations += s.iterations;
      total.milliseconds += s.milliseconds;
      total.cost_before = s.cost_before - earlier_change;
      total.cost_after = s.cost_after;
      total.moved_nodes = moved;
      earlier_change += s.cost_after - s.cost_before;
    };
    // Each window holds at least 4x the nodes of the one before, so a grown window is never
    // the same set solved again.
    for (std::size_t count = std::size_t(config.window_nodes);;) {
      std::size_t size = 0;
      std::vector<char> inside;
      const bool too_large =
          config.coarse_nodes > 0 && count > std::size_t(config.coarse_above_nodes);
      if (2 * count < solved_nodes() && !too_large) inside = window(count, size);
      if (inside.empty() || 2 * size >= solved_nodes()) {
        const GraphSolve all = solve_all();
        add(all, solved_nodes());
        total.whole_graph = true;
        total.coarse = all.coarse;
        if (all.coarse) {
          // What the coarse graph cannot hold (bends shorter than its spacing near what
          // changed) is solved in the first window, unless that is most of the graph (after
          // a long stretch without solves).
          std::size_t refined = 0;
          inside = window(std::size_t(config.window_nodes), refined);
          if (2 * refined < solved_nodes()) {
            const GraphSolve near = solve(&inside);
            total.iterations += near.iterations;
            total.milliseconds += near.milliseconds;
            total.cost_after += near.cost_after - near.cost_before;
          }
        }
        changed.clear();
        return total;
      }
      std::vector<std::pair<const Edge*, Eigen::Matrix<double, 6, 1>>> border;
      for (const Edge& e : edges) {
        if (e.active && inside[std::size_t(e.a)] != inside[std::size_t(e.b)]) {
          border.emplace_back(&e, residual(e));
        }
      }
      add(solve(&inside), size);
      double strain = 0;
      for (const auto& [e, before] : border) {
        strain = std::max(strain, (residual(*e) - before).norm());
      }
      if (strain <= config.max_border_strain) {
        approximate = true;
        changed.clear();
        return total;
      }
      count = 4 * std::max(count, size);
    }
  }

  // Drops the loop with the largest whitened residual while it is above the limit, solving
  // again after each (around the dropped loop when `local`).
  void drop_disagreeing_loops(GraphSolve& s, bool local) {
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
      changed.push_back(worst->a);
      changed.push_back(worst->b);
      const GraphSolve again = local ? solve_changed() : solve_whole();
      s.iterations += again.iterations;
      s.milliseconds += again.milliseconds;
      s.moved_nodes = std::max(s.moved_nodes, again.moved_nodes);
      s.whole_graph = s.whole_graph || again.whole_graph;
      s.coarse = s.coarse || again.coarse;
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
    for (const int end : {a, b}) {
      if (merged_into[std::size_t(end)] >= 0) {
        throw std::invalid_argument("pose graph: node " + std::to_string(end) +
                                    " was merged into node " +
                                    std::to_string(merged_into[std::size_t(end)]));
      }
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

  Eigen::Isometry3d pose_of(std::size_t i) const {
    const int into = merged_into.at(i);
    return into < 0 ? to_pose(nodes[i]) : pose_of(std::size_t(into)) * to_pose(nodes[i]);
  }

  void unlink(int node, int edge) {
    std::vector<int>& list = node_edges[std::size_t(node)];
    list.erase(std::remove(list.begin(), list.end(), edge), list.end());
  }

  void set_measurement(Edge& e, int a, int b, const Measurement& m) {
    const Edge moved = make_edge(a, b, m.T, m.C, e.loop);
    e.a = a, e.b = b;
    e.p_ab = moved.p_ab, e.q_ab = moved.q_ab, e.sqrt_info = moved.sqrt_info;
  }

  bool merge(int k, int loop_id) {
    if (k < 0 || std::size_t(k) >= nodes.size() || loop_id < 0 ||
        std::size_t(loop_id) >= edges.size()) {
      throw std::invalid_argument("pose graph: merge of node " + std::to_string(k) +
                                  " along edge " + std::to_string(loop_id) +
                                  ": no such node or edge");
    }
    Edge& link = edges[std::size_t(loop_id)];
    if (!link.loop || (link.a != k && link.b != k)) {
      throw std::invalid_argument("pose graph: edge " + std::to_string(loop_id) +
                                  " is not a loop of node " + std::to_string(k));
    }
    if (merged_into[std::size_t(k)] >= 0 || held(std::size_t(k)) || k == last_movable) {
      throw std::invalid_argument("pose graph: node " + std::to_string(k) +
                                  " cannot be merged (merged already, held, or the newest)");
    }
    if (!link.active) return false;
    const int p = link.a == k ? link.b : link.a;
    // T_k_p as the solves estimated it (every loop and odometry edge together, far better
    // known than by this loop alone), taken as exact from now on: the node becomes part of
    // the other, and its odometry edges keep their own covariances.
    const Eigen::Isometry3d T_kp =
        to_pose(nodes[std::size_t(k)]).inverse() * to_pose(nodes[std::size_t(p)]);
    link.active = false;
    link.absorbed = true;
    unlink(p, loop_id);
    changed.push_back(p);
    for (const int id : node_edges[std::size_t(k)]) {
      Edge& e = edges[std::size_t(id)];
      if (id == loop_id || !e.active) continue;
      const int x = e.a == k ? e.b : e.a;
      const Measurement xp = compose(e.b == k ? measurement(e) : inverse(measurement(e)), T_kp);
      changed.push_back(x);
      Edge* twin = nullptr;  // an odometry edge that already joins x and p
      if (x != p && !e.loop) {
        for (const int other : node_edges[std::size_t(x)]) {
          Edge& f = edges[std::size_t(other)];
          if (f.active && !f.loop && (f.a == p || f.b == p)) twin = &f;
        }
      }
      if (x == p || twin) {
        // (x == p: a measurement of T_p_k, which the merge fixes)
        if (twin) {
          const Measurement fused = twin->a == x ? fuse(measurement(*twin), xp)
                                                 : inverse(fuse(inverse(measurement(*twin)), xp));
          set_measurement(*twin, twin->a, twin->b, fused);
        }
        e.active = false;
        e.absorbed = true;
        unlink(x, id);
        continue;
      }
      set_measurement(e, x, p, xp);
      node_edges[std::size_t(p)].push_back(id);
    }
    std::vector<int>().swap(node_edges[std::size_t(k)]);
    nodes[std::size_t(k)] = to_node(T_kp.inverse());
    merged_into[std::size_t(k)] = p;
    ++merged_count;
    return true;
  }
};

void validate(const PoseGraphConfig& c) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(c.odometry_translation_per_m) || !positive(c.odometry_translation_min_m) ||
      !positive(c.odometry_rotation_deg_per_m) || !positive(c.odometry_rotation_min_deg) ||
      !positive(c.loop_translation_m) || !positive(c.loop_rotation_deg) ||
      !positive(c.max_loop_cost) || !positive(c.max_loop_residual) || c.max_iterations < 1 ||
      c.max_iterations > 10000 || c.window_nodes < 1 || !positive(c.max_border_strain) ||
      c.coarse_nodes < 0 || c.coarse_above_nodes < 1) {
    throw std::invalid_argument(
        "pose graph config: sigmas and limits must be finite and > 0, max_iterations in "
        "[1, 10000], window_nodes and coarse_above_nodes >= 1, coarse_nodes >= 0");
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
  const int previous = impl_->last_movable;
  int id;
  if (odometry && previous >= 0) {
    // The new node continues the previous one's current estimate, so its edge starts at rest.
    id =
        impl_->add_node(to_node(to_pose(impl_->nodes[std::size_t(previous)]) * (*odometry)), false);
    const PoseGraphConfig& c = impl_->config;
    const double d = odometry->translation().norm();
    impl_->add_edge(impl_->make_edge(
        previous, id, *odometry,
        std::max(c.odometry_translation_min_m, c.odometry_translation_per_m * d),
        kDeg * std::max(c.odometry_rotation_min_deg, c.odometry_rotation_deg_per_m * d), false));
  } else {
    id = impl_->add_node(to_node(initial), false);
    impl_->run_starts.push_back(id);
  }
  impl_->last_movable = id;
  return id;
}

int PoseGraph::add_fixed_node(const Eigen::Isometry3d& T_world_cam) {
  if (!T_world_cam.matrix().allFinite()) throw std::invalid_argument("pose graph: non-finite pose");
  impl_->has_fixed = true;
  return impl_->add_node(to_node(T_world_cam), true);
}

void PoseGraph::transform(const Eigen::Isometry3d& T_new_old) {
  for (std::size_t i = 0; i < impl_->nodes.size(); ++i) {
    if (!impl_->fixed[i] && impl_->merged_into[i] < 0)
      impl_->nodes[i] = to_node(T_new_old * to_pose(impl_->nodes[i]));
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
  return impl_->add_edge(impl_->loop_edge(a, b, T_a_b, covariance));
}

double PoseGraph::loop_residual(int a, int b, const Eigen::Isometry3d& T_a_b,
                                const Covariance6* covariance) const {
  return std::sqrt(impl_->edge_cost(impl_->loop_edge(a, b, T_a_b, covariance)));
}

bool PoseGraph::loop_active(int loop_id) const {
  if (loop_id < 0 || std::size_t(loop_id) >= impl_->edges.size()) return false;
  const Edge& e = impl_->edges[std::size_t(loop_id)];
  return e.loop && (e.active || e.absorbed);
}

GraphSolve PoseGraph::optimise() {
  GraphSolve s = impl_->solve_whole();
  impl_->drop_disagreeing_loops(s, false);
  return s;
}

GraphSolve PoseGraph::update() {
  GraphSolve s = impl_->solve_changed();
  if (s.ran) impl_->drop_disagreeing_loops(s, true);
  return s;
}

bool PoseGraph::approximate() const { return impl_->approximate; }

bool PoseGraph::merge(int node, int loop_id) { return impl_->merge(node, loop_id); }

bool PoseGraph::merged(int node) const {
  return impl_->merged_into.at(static_cast<std::size_t>(node)) >= 0;
}

std::size_t PoseGraph::solved_nodes() const { return impl_->solved_nodes(); }

std::size_t PoseGraph::solved_edges() const {
  std::size_t n = 0;
  for (const Edge& e : impl_->edges) n += e.active;
  return n;
}

bool PoseGraph::add_loop(int a, int b, const Eigen::Isometry3d& T_a_b, GraphSolve* solve,
                         int* loop_id, const Covariance6* covariance) {
  const std::vector<Node> before = impl_->nodes;
  const std::vector<int> changed_before = impl_->changed;
  const bool approximate_before = impl_->approximate;
  const int id = add_loop_unsolved(a, b, T_a_b, covariance);
  if (loop_id) *loop_id = id;
  const double loop_cost = 0.5 * impl_->edge_cost(impl_->edges.back());
  GraphSolve s = impl_->solve_changed();
  // The solve's costs include the new loop at the start: without it, the graph cost
  // before.
  bool kept = s.cost_after - (s.cost_before - loop_cost) <= impl_->config.max_loop_cost;
  if (!kept) {
    impl_->edges.back().active = false;  // kept inactive, so that ids stay valid
    impl_->nodes = before;
    impl_->changed = changed_before;
    impl_->approximate = approximate_before;
  } else {
    impl_->drop_disagreeing_loops(s, true);
    kept = impl_->edges.back().active;
  }
  if (solve) *solve = s;
  return kept;
}

std::size_t PoseGraph::size() const { return impl_->nodes.size(); }

Eigen::Isometry3d PoseGraph::pose(int node) const {
  return impl_->pose_of(static_cast<std::size_t>(node));
}

Eigen::Vector3d PoseGraph::position(int node) const {
  const std::size_t i = static_cast<std::size_t>(node);
  if (impl_->merged_into.at(i) >= 0) return impl_->pose_of(i).translation();
  const Node& n = impl_->nodes[i];
  return Eigen::Vector3d(n.p[0], n.p[1], n.p[2]);
}

std::size_t PoseGraph::loop_count() const {
  std::size_t n = 0;
  for (const Edge& e : impl_->edges) n += e.loop && (e.active || e.absorbed);
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
