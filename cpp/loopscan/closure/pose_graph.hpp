#pragma once
// A pose graph over keyframes: one SE(3) node (camera-to-world) per keyframe, odometry edges
// between consecutive keyframes of a VO run, loop edges from verified loops, solved with Ceres.
// A loop is kept only when the graph agrees with it: adding it may raise the optimised cost by
// at most `max_loop_cost` (whitened units, ~chi-square with 6 dof), and after every solve the
// loop with the largest whitened residual is dropped while it exceeds `max_loop_residual`.
// Online solves are local: only the nodes within a few edges of what changed move, the rest
// hold still; the window grows until the edges across its border carry no new strain, so a
// revisit of a corrected map costs milliseconds at any graph size while the first loop after a
// long drift still spreads over the whole lap (over a coarse graph once the window would be
// large). A node that revisits another can be merged into
// it (merge()), so a drive over the same places keeps the solves the size of the area.
#include <memory>
#include <vector>

#include <Eigen/Geometry>

namespace loopscan::closure {

// Covariance of a relative pose: translation (m, in the first node's frame), then rotation (rad).
using Covariance6 = Eigen::Matrix<double, 6, 6>;

struct PoseGraphConfig {
  // Odometry standard deviations grow with the distance d between the two keyframes:
  // sigma = max(min, per_m * d). Loose on purpose: a loop that needs more than this is suspect.
  double odometry_translation_per_m = 0.03;
  double odometry_translation_min_m = 0.02;
  double odometry_rotation_deg_per_m = 0.06;
  double odometry_rotation_min_deg = 0.05;
  double loop_translation_m = 1.5;  // verified loops err together (a revisit is one place)
  double loop_rotation_deg = 4.5;
  double max_loop_cost = 40.0;       // chi-square(6) at ~1e-6
  double max_loop_residual = 6.0;    // whitened norm of one loop's residual
  int max_iterations = 200;
  // Local solves (add_loop, update): the first window holds at least this many nodes nearest
  // (in edges) to what changed; it grows 4x while an edge across its border changed its
  // whitened residual by more than `max_border_strain`, and becomes the whole graph at half of
  // it (of the nodes not merged).
  bool incremental = true;
  int window_nodes = 300;
  double max_border_strain = 0.03;
  // Coarse solves: an online solve that would hold more than `coarse_above_nodes` nodes solves
  // the whole graph over about `coarse_nodes` nodes instead (evenly spaced nodes of each
  // odometry chain, and every node with a prior, a held pose or more than two odometry edges;
  // the chains between composed into one edge each, loops moved to the nearest of these nodes),
  // places the nodes between from their chain's measurements, then solves the first window
  // around what changed. A first loop after a long drift then costs tens of milliseconds at
  // 20k keyframes instead of a second; the answer is an approximation (optimise() and the
  // closers' finish() stay exact). coarse_nodes 0: never coarse.
  int coarse_nodes = 1000;
  int coarse_above_nodes = 1000;
};

void validate(const PoseGraphConfig& config);

struct GraphSolve {
  bool ran = false;
  int iterations = 0;
  // 0.5 * sum of squared whitened residuals of the edges the solve could change (every edge
  // when it was over the whole graph), before any loop was dropped and solved without.
  double cost_before = 0, cost_after = 0;
  double milliseconds = 0;
  int loops_dropped = 0;  // by the residual test during this solve
  std::size_t moved_nodes = 0;  // the largest window of this call (nodes, held ones included)
  bool whole_graph = false;     // a solve of this call was over every node
  bool coarse = false;          // ... through the coarse graph (see coarse_nodes)
};

class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphConfig& config = {});
  ~PoseGraph();
  PoseGraph(PoseGraph&&) noexcept;
  PoseGraph& operator=(PoseGraph&&) noexcept;

  // Appends a node. `odometry`: the VO's T_prev_this from the previous node added by add_node
  // (nullptr: a new VO run starts here, the node only gets a weak prior at `initial`).
  int add_node(const Eigen::Isometry3d& initial_T_world_cam,
               const Eigen::Isometry3d* odometry_T_prev_this = nullptr);

  // Appends a node that no solve moves: a place of a saved map (its pose in the map frame).
  // Once the graph has one, the first node is no longer held: the map fixes the frame.
  int add_fixed_node(const Eigen::Isometry3d& T_world_cam);

  // Re-expresses every movable node in another frame: T <- T_new_old * T (a session that
  // joins a saved map at its first loop).
  void transform(const Eigen::Isometry3d& T_new_old);

  // Proposes a loop T_a_b between nodes a and b, solves (locally, see update()), and keeps
  // the loop if the graph agrees (see the header comment); a refused loop leaves the graph as
  // it was, pending nodes and loops included.
  // Returns true when the loop was kept; `loop_id` (optional) receives its id.
  // `covariance`: what the loop's alignment measured (nullptr: the config's loop sigmas).
  bool add_loop(int a, int b, const Eigen::Isometry3d& T_a_b, GraphSolve* solve = nullptr,
                int* loop_id = nullptr, const Covariance6* covariance = nullptr);

  // Whitened residual norm a loop T_a_b would have at the current estimate.
  double loop_residual(int a, int b, const Eigen::Isometry3d& T_a_b,
                       const Covariance6* covariance = nullptr) const;

  // Adds a loop without solving (batch use); call optimise() afterwards. Returns its id.
  // (Loops, like every edge, throw for a merged node.)
  int add_loop_unsolved(int a, int b, const Eigen::Isometry3d& T_a_b,
                        const Covariance6* covariance = nullptr);
  // False once a solve dropped the loop (or the cost gate refused it).
  bool loop_active(int loop_id) const;
  // Solves the whole graph.
  GraphSolve optimise();
  // Solves around what changed since the last solve (new nodes and loops); the whole graph
  // when `incremental` is off. Does nothing when nothing changed.
  GraphSolve update();
  // True when a local solve ran since the last whole-graph one.
  bool approximate() const;

  // Folds `node` into the other end of `loop_id` (one of its active loops): the relative pose
  // the solves estimate between the two becomes exact, so the node's pose follows the other's
  // from now on, and its other edges move there composed with it (their covariances carried
  // over to first order). An odometry edge that then joins two nodes another odometry edge
  // joins is fused with it (information added), so laps over the same places add neither nodes
  // nor edges to the solves. Merge once the estimate has settled: no solve revisits what the
  // merge fixed. The loop counts as kept and no solve can drop it. Returns false (nothing
  // done) when the loop is not active. Throws for a held node, the node odometry continues
  // from, or one merged already; edges can no longer be added to a merged node.
  bool merge(int node, int loop_id);
  bool merged(int node) const;
  std::size_t solved_nodes() const;  // nodes a whole-graph solve holds (not merged)
  std::size_t solved_edges() const;  // its edges

  std::size_t size() const;
  Eigen::Isometry3d pose(int node) const;  // current estimate, camera-to-world
  Eigen::Vector3d position(int node) const;  // its translation (no rotation built)
  std::size_t loop_count() const;            // loops currently in the graph (merged ones too)
  // Whitened residual norm of every loop in the graph (not merged), at the current estimate.
  std::vector<double> loop_residuals() const;
  double cost() const;  // at the current estimate

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace loopscan::closure
