#pragma once
// Online loop closing on top of place recognition: per keyframe, imitate the scan, describe it,
// query the map, verify the candidates geometrically, accept the loops that neighbouring
// keyframes confirm, optimise the pose graph when a loop joins, and add the place to the map
// unless the map holds it already.
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "loopscan/closure/pose_graph.hpp"
#include "loopscan/closure/verification.hpp"
#include "loopscan/core/pipeline/recognizer.hpp"

namespace loopscan::closure {

// The pose with its rotation replaced by the nearest rotation (SVD): poses written with a few
// digits, or chained from such, are not quite orthonormal, and a rigid inverse of them
// misplaces points far from the origin (1e-4 of non-orthonormality at 1 km: 0.1 m a pose,
// compounding along the odometry). The closer takes every input pose through it.
KeyframePose orthonormalised(KeyframePose keyframe);
Eigen::Isometry3d isometry(const Pose3x4& T);  // a 3x4 [R | t] as a rigid transform

struct ConsistencyConfig {
  int required = 2;  // verified loops that agree, this one included
  int window = 4;    // ... among the last `window` described keyframes
  double max_translation_m = 1.0;
  double max_rotation_deg = 2.0;
};

// Places near the query in the current estimate of the trajectory are verified too: a revisit
// the descriptor misses (the other driving direction, another lane or season) is still found
// while the estimate is good enough, and every loop makes it better.
struct ProximityConfig {
  int candidates = 2;  // nearest places verified per keyframe (0: descriptor candidates only)
  double base_radius_m = 8.0;  // search radius just after a loop or at the start of a VO run ...
  double radius_per_m = 0.02;  // ... growing with the path travelled since (the VO's drift)
  double max_radius_m = 30.0;
  // A place where the estimate puts the query is likely the same place before any geometry is
  // seen (far likelier than the best of thousands of descriptor matches), so less overlap
  // suffices: the pose the alignment finds must still pass the graph's test.
  double min_overlap = 0.25;
};

// A described keyframe whose place the map already holds links to it instead of adding a copy,
// so the map grows with the area driven, not with time: held = a loop of this keyframe that
// verification passed (and the graph did not refuse) to a place of its own session within these
// bounds. Places of other sessions (another date or season) never absorb it: each session keeps
// its own appearance.
// Its graph node merges into the place's `merge_after_keyframes` described keyframes later
// (once later loops had their say on the link), so the pose graph grows with the area too.
struct LifelongConfig {
  bool enabled = true;
  double max_distance_m = 3.0;
  double max_rotation_deg = 15.0;
  bool merge_nodes = true;
  int merge_after_keyframes = 200;
};

struct LoopCloserConfig {
  RecognizerConfig recognition = RecognizerConfig::make(Method::ScanContext);
  int candidates = 3;  // best places verified per keyframe (first that passes wins)
  // Candidates whose descriptor distance is above this are not verified (the database's
  // fused z-score for Scan Context and M2DP: true revisits score far below -6, most wrong
  // places above; make() sets it per method, +inf: verify every candidate).
  double max_candidate_distance = std::numeric_limits<double>::infinity();
  CloudConfig cloud;
  NormalConfig normals;
  VerifyConfig verify;
  ConsistencyConfig consistency;
  ProximityConfig proximity;
  LoopUncertaintyConfig loop_uncertainty;  // what each loop edge's alignment measured
  LifelongConfig lifelong;
  PoseGraphConfig graph;
  // Solve the graph at most every this many keyframes while loops keep coming: loops the
  // current estimate already agrees with wait; any other (a new revisit) is solved at once,
  // through the graph's cost gate.
  int min_keyframes_between_solves = 10;
  // Threads for a candidate's alignments (its ICP starts, then its finalists), a place's plane
  // fits and the map's waiting places: the same loops, poses and clouds whatever the count.
  // Candidates are still verified one at a time, in order.
  int threads = 1;
  static LoopCloserConfig make(Method method, Mode mode = Mode::Default, double range_m = 45.0);
};

void validate(const LoopCloserConfig& config);

// Milliseconds, summed over keyframes. scan, describe and query are the caller's half
// (LoopCloser::prepare), the rest the integrating half.
struct StageTimes {
  double scan = 0, describe = 0, cloud = 0, query = 0, verify = 0, graph = 0;
  int keyframes = 0, described = 0, verifications = 0, solves = 0;
  int linked = 0;   // described keyframes linked to a place the map held (not added)
  int skipped = 0;  // described keyframes left unverified (BackgroundConfig::WhenFull)
  std::size_t graph_nodes = 0, graph_edges = 0;  // the pose graph's solved ones, at finish()
};

// The stages' mean milliseconds as `close` reports them: the scan and the graph per keyframe,
// the stages only a described keyframe runs per described keyframe, verification also per
// verified candidate and the graph per solve; 0 where nothing was counted.
struct StageMeans {
  double scan = 0, describe = 0, cloud = 0, query = 0, verify = 0, graph = 0;
  double per_verification = 0, per_solve = 0;
};
StageMeans stage_means(const StageTimes& times);

struct KeyframeClosure {
  int keyframe = 0;
  bool described = false;
  std::vector<Candidate> candidates;
  std::vector<Loop> verified;  // every verification of this keyframe, verdicts included
  std::vector<Loop> accepted;  // loops that joined the graph now (may include earlier pending)
  GraphSolve solve;
  // Database index of the place this described keyframe linked to instead of joining the map
  // (LifelongConfig); -1: it joined.
  long linked_place = -1;
  // Described, but neither verified nor added to the map: a background closer's worker was
  // too far behind (BackgroundConfig::WhenFull::SkipVerification). Its graph node is there.
  bool skipped = false;
};

// A keyframe after the caller's half of the work (LoopCloser::prepare): its scan described and
// the map queried; what integrate() needs to verify it and add it to the graph and the map.
struct PreparedKeyframe {
  KeyframePose keyframe;  // orthonormalised
  bool reset = false;
  bool has_scan = false;
  // Among all keyframes given, from 0: the keyframes a VO reset leaves undescribed (the scan
  // building up again) count, so the places just before the reset leave the recent band.
  long ordinal = -1;
  PlaceDescriptor place;
  Points3f raw;  // the scan's points in range, unfiltered: the cloud verification aligns
  KeyframeClosure out;
  // Drops the place: integrate() then adds the graph node only (out.skipped).
  void skip();
};

class LoopCloser {
 public:
  explicit LoopCloser(const LoopCloserConfig& config);
  // Continues a saved map (other sessions' places, their poses in the map frame, and one cloud
  // per place): this session lives in its VO frame until its first accepted loop into the map,
  // then in the map's frame. Throws std::invalid_argument when the map's method differs,
  // clouds are missing, a place has no pose or already has this session's id.
  LoopCloser(const LoopCloserConfig& config, Database map, std::vector<PlaceCloud> map_clouds);

  // points: those the VO exported with this keyframe (its world frame); reset: the VO restarted.
  KeyframeClosure add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                               std::size_t n_points, bool reset = false);

  // A place from a real sensor instead of the VO: its points in range, in the camera
  // convention (x right, y down, z forward; see lidar_scan.hpp for LiDAR scans), at `keyframe`'s
  // pose. Filtered and described like an imitated scan; every step after is add_keyframe's.
  KeyframeClosure add_scan(const KeyframePose& keyframe, const Cloud& in_range, bool reset = false);

  // add_keyframe in two halves, for a caller that runs them on two threads: prepare() imitates
  // and describes the scan and queries the map; integrate() builds the place's cloud, verifies
  // the candidates, joins the graph and the map. prepare() may run while integrate() runs on
  // another thread (one call of each at a time); integrate() takes every prepared keyframe, in
  // prepare's order. add_keyframe(...) == integrate(prepare(...)).
  PreparedKeyframe prepare(const KeyframePose& keyframe, const IdPoint* points,
                           std::size_t n_points, bool reset = false);
  PreparedKeyframe prepare_scan(const KeyframePose& keyframe, const Cloud& in_range,
                                bool reset = false);
  KeyframeClosure integrate(PreparedKeyframe prepared);

  // Solves the graph once more if loops joined since the last solve (end of a run).
  GraphSolve finish();
  // Grows whenever the graph's estimate of earlier poses changes (a solve, the anchoring).
  long pose_revision() const { return pose_revision_; }

  // True once this session's poses are in the map's frame (always, without a saved map).
  bool anchored() const { return anchored_; }
  int anchored_at() const { return anchored_at_; }  // query keyframe of the anchoring loop

  // Corrected world-to-camera pose of every keyframe integrated so far, in input order; from
  // `first` on.
  std::vector<KeyframePose> corrected_poses(std::size_t first = 0) const;
  // The map with this session's places at their corrected poses (in the map's frame once
  // anchored): what a later session continues.
  Database corrected_map() const;
  const std::vector<Loop>& loops() const { return loops_; }  // every verification, in order
  const Database& database() const { return db_; }
  // Every place's cloud, classifying those no verification has needed yet (on config().threads
  // threads, a place each).
  std::vector<PlaceCloud> place_clouds() const;
  // Places still kept as voxel clouds (CloudConfig::max_unclassified_places).
  std::size_t unclassified_places() const { return unclassified_; }
  const StageTimes& times() const { return times_; }
  const LoopCloserConfig& config() const { return config_; }

 private:
  struct Verified {
    Loop loop;
    std::size_t place_index;  // in the database
    int described_at;         // count of described keyframes when verified
    bool in_graph;
  };
  int add_graph_node(const KeyframePose& keyframe, bool reset);
  PreparedKeyframe begin_keyframe(const KeyframePose& keyframe, bool reset);
  void describe_and_query(const Cloud& scan, PreparedKeyframe& prepared);
  // The query's band of recent places: those of the last exclude_recent keyframes
  // (their count, at the end of the database, when the keyframe of this ordinal is queried).
  long recent_places(long ordinal) const;
  // Steps 4-7 of a described keyframe: cloud, verify, confirm, join the graph and the map.
  void close_place(PreparedKeyframe& prepared, KeyframeClosure& out);
  struct Proposal {
    Candidate candidate;
    std::optional<Eigen::Isometry3d> predicted;  // T_query_match from the estimate (nearby places)
  };
  std::vector<Proposal> nearby_places(int keyframe_id, long ordinal,
                                      const std::vector<Candidate>& taken);
  // A place's pose in the world estimate: the graph's for this session's places, the saved
  // map's otherwise (none when the map has no poses).
  std::optional<Eigen::Isometry3d> place_pose(std::size_t index) const;
  // The root run a place's pose is in: its keyframe's, or the saved map's (-1: no map run).
  int run_of_place(const PlaceRef& place);
  QueryPlacement placement_of(const Loop& loop);  // framed by run_of_place
  // The query keyframe's target cloud, built for its first verification: most keyframes
  // verify nothing.
  struct QueryCloud {
    const Points3f& voxels;
    const NormalConfig& normals;
    std::optional<TargetCloud> target;
    const TargetCloud& get();
  };
  // Builds what it needs of the clouds on the cloud stage's clock.
  std::vector<Loop> verify(QueryCloud& query, const BirdsEyeGrid* birds_eye, int keyframe_id,
                           const std::vector<Proposal>& proposals, std::size_t& last_place_index,
                           std::vector<QueryPlacement>& earlier);
  // A map place's cloud, classified (a plane fit per point) on its first use.
  const PlaceCloud& place_cloud(std::size_t index) const;
  int root(int run);  // the representative of the runs joined by loops
  int run_of(std::size_t pose_index) { return root(run_[pose_index]); }
  std::vector<Loop> confirm(const Loop& loop, std::size_t place_index);
  bool consistent(const Verified& earlier, const Loop& loop, std::size_t place_index) const;
  Eigen::Isometry3d vo_T_world_cam(int keyframe_id) const;
  void update_verdicts(KeyframeClosure& out);
  void join_graph(KeyframeClosure& out);  // the accepted loops' edges, and a solve if due
  long held_place(int keyframe_id, const KeyframeClosure& out) const;
  void merge_linked_nodes();
  int match_node(const Loop& loop);
  void anchor(const Loop& loop, int query_node);

  LoopCloserConfig config_;
  // The caller's half (prepare): the imitator and the ids seen. The database is read there
  // under a shared lock; integrate() adds to it under the exclusive one.
  ScanImitator imitator_;
  std::unordered_set<int> prepared_ids_;
  std::unique_ptr<std::shared_mutex> db_mutex_ = std::make_unique<std::shared_mutex>();
  Database db_;
  std::vector<long> place_ordinal_;  // per database place: its keyframe's ordinal
  // Per database place: its cloud, or until a verification needs it (most places are never a
  // candidate) its voxel cloud, the input of the classification.
  struct StoredCloud {
    PlaceCloud cloud;
    Points3f voxels;  // non-empty: not classified yet
  };
  // Classifies a place kept as voxels, its plane fits on `threads` threads (touches nothing
  // else: several places may be classified at once).
  void classify(StoredCloud& stored, int threads) const;
  mutable std::vector<StoredCloud> clouds_;
  mutable std::size_t unclassified_ = 0;         // places whose voxels are kept
  mutable std::size_t oldest_unclassified_ = 0;  // no unclassified place before this index
  PoseGraph graph_;
  std::vector<KeyframePose> input_poses_;
  std::unordered_map<int, std::size_t> pose_index_;  // keyframe id -> input_poses_ index
  std::vector<int> graph_node_;                      // per input pose
  std::vector<double> path_m_;                       // per input pose: VO path length so far
  std::vector<int> run_;                             // per input pose: its VO run
  std::vector<int> run_parent_;                      // union-find over runs joined by loops
  int map_run_ = -1;                                 // the saved map's places, as one run
  std::vector<double> loop_paths_m_;                 // path_m_ of each loop edge's query
  std::unordered_map<std::size_t, int> map_node_;    // saved-map place -> fixed graph node
  bool anchored_ = true;
  int anchored_at_ = -1;
  std::deque<Verified> recent_;
  std::vector<Loop> loops_;
  std::map<std::pair<int, std::size_t>, std::size_t> loop_index_;  // (query, place) -> loops_
  std::vector<std::pair<std::size_t, int>> graph_loops_;           // loops_ index, graph loop id
  struct Link {
    std::size_t loop;  // loops_ index of the linking loop
    int described_at;
  };
  std::deque<Link> links_;  // linked keyframes whose nodes are not merged yet
  StageTimes times_;
  int described_ = 0;
  int last_solve_at_ = -1000000;
  bool unsolved_loops_ = false;
  long pose_revision_ = 0;
};

// Re-expresses VO points with corrected poses: each point keeps its place in its keyframe's
// camera frame. Points of keyframes missing from either list are dropped.
std::vector<IdPoint> reexpress_points(const std::vector<IdPoint>& points,
                                      const std::vector<KeyframePose>& vo_poses,
                                      const std::vector<KeyframePose>& corrected_poses);

}  // namespace loopscan::closure
