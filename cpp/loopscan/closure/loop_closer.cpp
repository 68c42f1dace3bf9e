#include "loopscan/closure/loop_closer.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/SVD>

#include "loopscan/core/database/database_checks.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/timing.hpp"

namespace loopscan::closure {
namespace {

double rotation_angle(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle(); }

}  // namespace

Eigen::Isometry3d isometry(const Pose3x4& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = T.leftCols<3>();
  out.translation() = T.col(3);
  return out;
}

KeyframePose orthonormalised(KeyframePose k) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(Eigen::Matrix3d(k.T_cam_world.leftCols<3>()),
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) {
    Eigen::Matrix3d U = svd.matrixU();
    U.col(2) *= -1;
    R = U * svd.matrixV().transpose();
  }
  k.T_cam_world.leftCols<3>() = R;
  return k;
}

LoopCloserConfig LoopCloserConfig::make(Method method, Mode mode, double range_m) {
  LoopCloserConfig c;
  c.recognition = RecognizerConfig::make(method, mode, range_m);
  if (distance_components(method) == 2 && c.recognition.database.fusion == Fusion::Fused) {
    c.max_candidate_distance = -6.0;
  }
  return c;
}

StageMeans stage_means(const StageTimes& t) {
  const auto mean = [](double total_ms, int count) { return count > 0 ? total_ms / count : 0.0; };
  StageMeans m;
  m.scan = mean(t.scan, t.keyframes);
  m.describe = mean(t.describe, t.described);
  m.cloud = mean(t.cloud, t.described);
  m.query = mean(t.query, t.described);
  m.verify = mean(t.verify, t.described);
  m.graph = mean(t.graph, t.keyframes);
  m.per_verification = mean(t.verify, t.verifications);
  m.per_solve = mean(t.graph, t.solves);
  return m;
}

void validate(const LoopCloserConfig& c) {
  if (c.recognition.imitation.lookahead_m > 0 && c.recognition.imitation.mode == Mode::Default) {
    throw std::invalid_argument(
        "LoopCloserConfig: the loop closer takes forward-only scans (imitation.lookahead_m = 0): "
        "it verifies each keyframe and adds it to the graph as the keyframe arrives");
  }
  if (c.threads < 1 || c.threads > 256) {
    throw std::invalid_argument("loop closer config: threads: expected 1 to 256, got " +
                                std::to_string(c.threads));
  }
  validate(c.cloud);
  validate(c.verify);
  validate(c.graph);
  validate(c.loop_uncertainty);
  const ConsistencyConfig& k = c.consistency;
  if (c.candidates < 1 || c.candidates > 100 || k.required < 1 || k.required > 100 ||
      k.window < 1 || k.window > 1000 || !(k.max_translation_m > 0) || !(k.max_rotation_deg > 0) ||
      !std::isfinite(k.max_translation_m) || !std::isfinite(k.max_rotation_deg) ||
      c.min_keyframes_between_solves < 0) {
    throw std::invalid_argument(
        "loop closer config: candidates in [1, 100], consistency required in [1, 100], window in "
        "[1, 1000], tolerances finite and > 0, min_keyframes_between_solves >= 0");
  }
  const ProximityConfig& p = c.proximity;
  if (p.candidates < 0 || p.candidates > 100 || !(p.base_radius_m >= 0) ||
      !(p.radius_per_m >= 0 && p.radius_per_m <= 10) || !(p.max_radius_m >= 0) ||
      !(p.max_radius_m <= 1e4) || !(p.base_radius_m <= 1e4) ||
      !(p.min_overlap >= 0 && p.min_overlap <= 1)) {
    throw std::invalid_argument(
        "loop closer config: proximity candidates in [0, 100], radii in [0, 10000] m, "
        "radius_per_m in [0, 10], min_overlap in [0, 1]");
  }
  const LifelongConfig& l = c.lifelong;
  if (!(l.max_distance_m >= 0 && l.max_distance_m <= 1e3) ||
      !(l.max_rotation_deg >= 0 && l.max_rotation_deg <= 180) ||
      !(l.merge_after_keyframes >= 1 && l.merge_after_keyframes <= 1000000)) {
    throw std::invalid_argument(
        "loop closer config: lifelong max_distance_m in [0, 1000], max_rotation_deg in [0, 180], "
        "merge_after_keyframes in [1, 1000000]");
  }
}

LoopCloser::LoopCloser(const LoopCloserConfig& config)
    : LoopCloser(config, Database(map_config(config.recognition)), {}) {}

LoopCloser::LoopCloser(const LoopCloserConfig& config, Database map,
                       std::vector<PlaceCloud> map_clouds)
    : config_(config),
      imitator_(config.recognition.imitation),
      db_(std::move(map)),
      graph_(config.graph) {
  validate(config_);
  if (map_clouds.size() != db_.size()) {
    throw std::invalid_argument("loop closer: the map has " + std::to_string(db_.size()) +
                                " places but " + std::to_string(map_clouds.size()) +
                                " place clouds (a map saved without clouds cannot verify loops)");
  }
  require_same_description(db_.config(), map_config(config_.recognition), "loop closer");
  for (std::size_t i = 0; i < db_.size(); ++i) {
    if (db_.place(i).session == config_.recognition.session) {
      throw std::invalid_argument("loop closer: the map already has places of session " +
                                  std::to_string(config_.recognition.session));
    }
    if (!db_.pose(i)) throw std::invalid_argument("loop closer: a map place has no pose");
  }
  for (PlaceCloud& cloud : map_clouds) clouds_.push_back({std::move(cloud), {}});
  place_ordinal_.assign(db_.size(), std::numeric_limits<long>::min());  // never recent
  anchored_ = db_.size() == 0;
  if (!anchored_) {
    map_run_ = 0;
    run_parent_.push_back(0);
  }
}

int LoopCloser::match_node(const Loop& loop) {
  if (loop.match.session == config_.recognition.session) {
    return graph_node_[pose_index_.at(loop.match.keyframe)];
  }
  const auto it = map_node_.find(loop.place_index);
  if (it != map_node_.end()) return it->second;
  const int node = graph_.add_fixed_node(isometry(*db_.pose(loop.place_index)).inverse());
  map_node_[loop.place_index] = node;
  return node;
}

// The first loop into the saved map puts this session into the map's frame.
void LoopCloser::anchor(const Loop& loop, int query_node) {
  const Eigen::Isometry3d T_map_match = isometry(*db_.pose(loop.place_index)).inverse();
  const Eigen::Isometry3d T_map_query = T_map_match * loop.T_query_match.inverse();
  graph_.transform(T_map_query * graph_.pose(query_node).inverse());
  ++pose_revision_;
  anchored_ = true;
  anchored_at_ = loop.query;
}

int LoopCloser::add_graph_node(const KeyframePose& keyframe, bool reset) {  // orthonormalised
  const Eigen::Isometry3d T_world_cam = isometry(keyframe.T_cam_world).inverse();
  int node;
  if (input_poses_.empty() || reset) {
    node = graph_.add_node(T_world_cam);
    run_parent_.push_back(int(run_parent_.size()));
    path_m_.push_back(path_m_.empty() ? 0.0 : path_m_.back());
  } else {
    const Eigen::Isometry3d odometry =
        isometry(input_poses_.back().T_cam_world) * T_world_cam;  // T_prev_this
    node = graph_.add_node(T_world_cam, &odometry);
    path_m_.push_back(path_m_.back() + odometry.translation().norm());
  }
  run_.push_back(int(run_parent_.size()) - 1);
  pose_index_[keyframe.id] = input_poses_.size();
  input_poses_.push_back(keyframe);
  graph_node_.push_back(node);
  return node;
}

Eigen::Isometry3d LoopCloser::vo_T_world_cam(int keyframe_id) const {
  return isometry(input_poses_[pose_index_.at(keyframe_id)].T_cam_world).inverse();
}

int LoopCloser::root(int run) {
  while (run_parent_[std::size_t(run)] != run) {
    run = run_parent_[std::size_t(run)] = run_parent_[std::size_t(run_parent_[std::size_t(run)])];
  }
  return run;
}

// The places nearest to the query's estimated position, within a radius that grows with the
// path travelled since the two could last be tied together (a loop, or the same VO run).
std::vector<LoopCloser::Proposal> LoopCloser::nearby_places(int keyframe_id, long ordinal,
                                                            const std::vector<Candidate>& taken) {
  const ProximityConfig& p = config_.proximity;
  std::vector<Proposal> out;
  if (p.candidates <= 0) return out;
  const std::size_t qi = pose_index_.at(keyframe_id);
  const Eigen::Vector3d query_position = graph_.position(graph_node_[qi]);
  const double since_loop = loop_paths_m_.empty() ? HUGE_VAL : path_m_[qi] - loop_paths_m_.back();
  const int query_run = run_of(qi);
  const bool map_tied = map_run_ >= 0 && root(map_run_) == query_run;
  const long searchable = long(db_.size()) - recent_places(ordinal);
  // Positions first (every place, every keyframe); whole poses only for the places in range.
  std::vector<std::pair<double, std::size_t>> found;  // distance, place index
  for (long i = 0; i < searchable; ++i) {
    const std::size_t index = std::size_t(i);
    const PlaceRef place = db_.place(index);
    Eigen::Vector3d position;
    double path_between = HUGE_VAL;
    if (place.session == config_.recognition.session) {
      const std::size_t pi = pose_index_.at(place.keyframe);
      if (run_of(pi) != query_run) continue;  // not yet tied to the query's run
      if (run_[pi] == run_[qi]) path_between = path_m_[qi] - path_m_[pi];
      position = graph_.position(graph_node_[pi]);
    } else {
      if (!map_tied) continue;
      const std::optional<Pose3x4> T_cam_world = db_.pose(index);  // a copy: pose() returns one
      if (!T_cam_world) continue;
      position = camera_centre(*T_cam_world);
    }
    const double radius = std::min(
        p.max_radius_m, p.base_radius_m + p.radius_per_m * std::min(path_between, since_loop));
    const double d = (position - query_position).norm();
    if (!(d <= radius)) continue;
    bool descriptor_has_it = false;
    for (const Candidate& c : taken) descriptor_has_it |= c.index == index;
    if (!descriptor_has_it) found.push_back({d, index});
  }
  const std::size_t n = std::min(found.size(), std::size_t(p.candidates));
  std::partial_sort(found.begin(), found.begin() + long(n), found.end());
  const Eigen::Isometry3d T_world_query = graph_.pose(graph_node_[qi]);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t index = found[k].second;
    const Eigen::Isometry3d T_world_place = *place_pose(index);
    Proposal proposal;
    proposal.candidate.place = db_.place(index);
    proposal.candidate.index = index;
    proposal.candidate.distance = std::numeric_limits<double>::quiet_NaN();
    proposal.predicted = T_world_query.inverse() * T_world_place;
    out.push_back(proposal);
  }
  return out;
}

std::optional<Eigen::Isometry3d> LoopCloser::place_pose(std::size_t index) const {
  const PlaceRef place = db_.place(index);
  if (place.session == config_.recognition.session) {
    return graph_.pose(graph_node_[pose_index_.at(place.keyframe)]);
  }
  const std::optional<Pose3x4> T_cam_world = db_.pose(index);
  if (!T_cam_world) return std::nullopt;
  return isometry(*T_cam_world).inverse();
}

int LoopCloser::run_of_place(const PlaceRef& place) {
  if (place.session == config_.recognition.session) return run_of(pose_index_.at(place.keyframe));
  return map_run_ < 0 ? -1 : root(map_run_);
}

QueryPlacement LoopCloser::placement_of(const Loop& loop) {
  const std::optional<Eigen::Isometry3d> T_world_place = place_pose(loop.place_index);
  const int frame = run_of_place(loop.match);
  if (!T_world_place || frame < 0) return {};
  return placement(loop, *T_world_place, frame);
}

const TargetCloud& LoopCloser::QueryCloud::get() {
  if (!target) target.emplace(voxels, normals);
  return *target;
}

void LoopCloser::classify(StoredCloud& stored, int threads) const {
  stored.cloud = to_place_cloud(TargetCloud(std::exchange(stored.voxels, {}), config_.normals),
                                kPlaceCloudPoints, kGroundMinVertical, threads);
}

const PlaceCloud& LoopCloser::place_cloud(std::size_t index) const {
  StoredCloud& stored = clouds_[index];
  if (!stored.voxels.empty()) {
    classify(stored, config_.threads);
    --unclassified_;
  }
  return stored.cloud;
}

std::vector<PlaceCloud> LoopCloser::place_clouds() const {
  std::vector<StoredCloud*> waiting;
  for (StoredCloud& stored : clouds_) {
    if (!stored.voxels.empty()) waiting.push_back(&stored);
  }
  for_each_index(waiting.size(), config_.threads,
                 [&](std::size_t i) { classify(*waiting[i], 1); });
  unclassified_ -= waiting.size();
  std::vector<PlaceCloud> out;
  out.reserve(clouds_.size());
  for (const StoredCloud& stored : clouds_) out.push_back(stored.cloud);
  return out;
}

std::vector<Loop> LoopCloser::verify(QueryCloud& query, const BirdsEyeGrid* birds_eye,
                                     int keyframe_id, const std::vector<Proposal>& proposals,
                                     std::size_t& last_place_index,
                                     std::vector<QueryPlacement>& earlier) {
  std::vector<Loop> out;
  for (const Proposal& proposal : proposals) {
    const Candidate& c = proposal.candidate;
    if (!proposal.predicted && !(c.distance <= config_.max_candidate_distance)) continue;
    const std::vector<Eigen::Isometry3d> guesses =
        proposal.predicted ? std::vector<Eigen::Isometry3d>{*proposal.predicted} : yaw_guesses(c);
    VerifyConfig verify_config = config_.verify;
    if (proposal.predicted) verify_config.min_overlap = config_.proximity.min_overlap;
    // The bird's-eye search seeds nearby places only: their predicted pose, which the loop
    // must agree with, bounds it. Around a descriptor candidate, which carries no position, it
    // finds slid alignments of a repeating street as readily as the true one (on the reverse
    // route, places 15 m away aligned 7 m slid and passed).
    const BirdsEyeGrid* grid = proposal.predicted ? birds_eye : nullptr;
    const TargetCloud* target = nullptr;
    const PlaceCloud* place = nullptr;
    {
      const ScopedTimer timer(times_.cloud);
      target = &query.get();
      place = &place_cloud(c.index);
    }
    Loop loop = verify_candidate(*target, *place, guesses, verify_config, grid, config_.threads);
    loop.nearby = proposal.predicted.has_value();
    loop.query = keyframe_id;
    loop.match = c.place;
    loop.distance = c.distance;
    loop.place_index = c.index;
    const QueryPlacement placed = placement_of(loop);
    if (loop.verdict == Verdict::Accepted && placed_elsewhere(placed, earlier, config_.verify)) {
      loop.verdict = Verdict::Ambiguous;
    }
    earlier.push_back(placed);
    ++times_.verifications;
    out.push_back(loop);
    last_place_index = c.index;
    if (loop.verdict == Verdict::Accepted) break;
  }
  return out;
}

void PreparedKeyframe::skip() {
  if (!has_scan) return;
  place = {};
  raw = {};
  out.skipped = true;
}

long LoopCloser::recent_places(long ordinal) const {
  const long band = config_.recognition.query.exclude_recent;
  const auto first = std::lower_bound(place_ordinal_.begin(), place_ordinal_.end(), ordinal - band);
  return long(place_ordinal_.end() - first);
}

PreparedKeyframe LoopCloser::begin_keyframe(const KeyframePose& keyframe, bool reset) {
  if (!keyframe.T_cam_world.allFinite()) {
    throw std::invalid_argument("loop closer: keyframe " + std::to_string(keyframe.id) +
                                " has a non-finite pose");
  }
  if (!prepared_ids_.insert(keyframe.id).second) {
    throw std::invalid_argument("loop closer: keyframe id " + std::to_string(keyframe.id) +
                                " given twice");
  }
  PreparedKeyframe prepared;
  prepared.ordinal = times_.keyframes++;
  prepared.keyframe = orthonormalised(keyframe);
  prepared.reset = reset;
  prepared.out.keyframe = keyframe.id;
  return prepared;
}

PreparedKeyframe LoopCloser::prepare(const KeyframePose& keyframe, const IdPoint* points,
                                     std::size_t n_points, bool reset) {
  PreparedKeyframe prepared = begin_keyframe(keyframe, reset);
  Cloud scan;
  {
    const ScopedTimer timer(times_.scan);
    prepared.has_scan = imitator_.next_scan(keyframe, points, n_points, reset,
                                            filter_for(config_.recognition.method), scan);
    if (prepared.has_scan) imitator_.last_in_range(prepared.raw);
  }
  if (prepared.has_scan) describe_and_query(scan, prepared);
  return prepared;
}

PreparedKeyframe LoopCloser::prepare_scan(const KeyframePose& keyframe, const Cloud& in_range,
                                          bool reset) {
  PreparedKeyframe prepared = begin_keyframe(keyframe, reset);
  Cloud scan;
  {
    const ScopedTimer timer(times_.scan);
    scan = filter_scan(in_range, filter_for(config_.recognition.method),
                       config_.recognition.imitation);
    for (const PointI& p : in_range) prepared.raw.push_back(p.p.cast<float>());
  }
  prepared.has_scan = true;
  describe_and_query(scan, prepared);
  return prepared;
}

KeyframeClosure LoopCloser::add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                         std::size_t n_points, bool reset) {
  return integrate(prepare(keyframe, points, n_points, reset));
}

KeyframeClosure LoopCloser::add_scan(const KeyframePose& keyframe, const Cloud& in_range,
                                     bool reset) {
  return integrate(prepare_scan(keyframe, in_range, reset));
}

void LoopCloser::describe_and_query(const Cloud& scan, PreparedKeyframe& prepared) {
  {
    const ScopedTimer timer(times_.describe);
    prepared.place.signature = describe(config_.recognition.method, scan,
                                        config_.recognition.descriptors, &prepared.place.frame);
  }
  prepared.out.described = true;
  const ScopedTimer timer(times_.query);
  const std::shared_lock lock(*db_mutex_);
  // Keyframes prepared but not integrated yet have no place: the band counts keyframes, so a
  // query sees the same places whenever integrate() runs (up to exclude_recent behind).
  QueryOptions options = config_.recognition.query;
  options.exclude_recent = int(recent_places(prepared.ordinal));
  prepared.out.candidates = db_.query(prepared.place, config_.candidates, options);
}

KeyframeClosure LoopCloser::integrate(PreparedKeyframe prepared) {
  KeyframeClosure out = std::move(prepared.out);
  {
    const ScopedTimer timer(times_.graph);
    add_graph_node(prepared.keyframe, prepared.reset);
    merge_linked_nodes();
  }
  if (!prepared.has_scan) return out;
  if (out.skipped) {
    ++times_.skipped;
    return out;
  }
  close_place(prepared, out);
  return out;
}

void LoopCloser::close_place(PreparedKeyframe& prepared, KeyframeClosure& out) {
  const KeyframePose& keyframe = prepared.keyframe;
  Points3f voxels;
  QueryCloud query{voxels, config_.normals, std::nullopt};
  StoredCloud stored;
  std::optional<BirdsEyeGrid> birds_eye;
  {
    const ScopedTimer timer(times_.cloud);
    voxels = voxel_cloud(prepared.raw, config_.cloud);
    if (config_.verify.birds_eye.enabled) {  // the grid needs the classified cloud now
      stored.cloud =
          to_place_cloud(query.get(), kPlaceCloudPoints, kGroundMinVertical, config_.threads);
      birds_eye.emplace(stored.cloud, config_.verify.birds_eye);
    }
  }
  ++described_;
  ++times_.described;
  // Verify the candidates, confirm by consistency.
  const double cloud_before = times_.cloud;  // verify() times the clouds it builds as cloud
  {
    const ScopedTimer timer(times_.verify);
    std::size_t index = 0;  // database place of the last verification
    std::vector<Proposal> proposals;
    for (const Candidate& c : out.candidates) proposals.push_back({c, std::nullopt});
    const BirdsEyeGrid* grid = birds_eye ? &*birds_eye : nullptr;
    std::vector<QueryPlacement> earlier;  // where each verified candidate put the query
    out.verified = verify(query, grid, keyframe.id, proposals, index, earlier);
    if (out.verified.empty() || out.verified.back().verdict != Verdict::Accepted) {
      const std::vector<Loop> nearby =
          verify(query, grid, keyframe.id,
                 nearby_places(keyframe.id, prepared.ordinal, out.candidates), index, earlier);
      out.verified.insert(out.verified.end(), nearby.begin(), nearby.end());
    }
    if (!out.verified.empty()) {
      Loop& last = out.verified.back();
      if (last.verdict == Verdict::Accepted) {
        last.verdict = Verdict::Pending;
        out.accepted = confirm(last, index);
      }
    }
    for (const Loop& v : out.verified) {
      loop_index_[{v.query, v.place_index}] = loops_.size();
      loops_.push_back(v);
    }
  }
  times_.verify -= times_.cloud - cloud_before;
  // Loop edges, and a solve when the revisit is new (or enough keyframes passed).
  {
    const ScopedTimer timer(times_.graph);
    join_graph(out);
  }
  // Join the map, unless the place is held already.
  out.linked_place = held_place(keyframe.id, out);
  if (out.linked_place >= 0) {
    ++times_.linked;
    if (config_.lifelong.merge_nodes) {
      links_.push_back({loop_index_.at({keyframe.id, std::size_t(out.linked_place)}), described_});
    }
    return;
  }
  {
    const std::unique_lock lock(*db_mutex_);
    db_.add({config_.recognition.session, keyframe.id}, prepared.place, keyframe.T_cam_world);
    place_ordinal_.push_back(prepared.ordinal);
  }
  if (!birds_eye && !voxels.empty()) {
    stored.voxels = std::move(voxels);
    ++unclassified_;
  }
  clouds_.push_back(std::move(stored));
  const ScopedTimer timer(times_.cloud);
  while (unclassified_ > std::size_t(config_.cloud.max_unclassified_places)) {
    while (clouds_[oldest_unclassified_].voxels.empty()) ++oldest_unclassified_;
    place_cloud(oldest_unclassified_);
  }
}

long LoopCloser::held_place(int keyframe_id, const KeyframeClosure& out) const {
  const LifelongConfig& l = config_.lifelong;
  if (!l.enabled) return -1;
  // Its own loops that verification passed: joined the graph, or waiting for confirmation (a
  // wrong one costs a place of the map, never a wrong edge).
  for (const Loop& loop : out.verified) {
    if (loop.query != keyframe_id ||
        (loop.verdict != Verdict::Accepted && loop.verdict != Verdict::Pending) ||
        loop.match.session != config_.recognition.session)
      continue;
    if (loop.T_query_match.translation().norm() <= l.max_distance_m &&
        rotation_angle(loop.T_query_match.rotation()) <= l.max_rotation_deg * M_PI / 180.0)
      return static_cast<long>(loop.place_index);
  }
  return -1;
}

// A linked keyframe's node folds into its place's once the link's loop has stood for a while
// in the graph; a link whose loop never joined it, or was dropped, keeps its node.
void LoopCloser::merge_linked_nodes() {
  while (!links_.empty() &&
         described_ - links_.front().described_at >= config_.lifelong.merge_after_keyframes) {
    const std::size_t loop = links_.front().loop;
    links_.pop_front();
    for (auto it = graph_loops_.rbegin(); it != graph_loops_.rend(); ++it) {
      if (it->first != loop) continue;
      graph_.merge(graph_node_[pose_index_.at(loops_[loop].query)], it->second);
      break;
    }
  }
}

void LoopCloser::join_graph(KeyframeClosure& out) {
  for (Loop& loop : out.accepted) {
    loop.verdict = Verdict::Accepted;
    const int a = graph_node_[pose_index_.at(loop.query)];
    if (!anchored_ && loop.match.session != config_.recognition.session) anchor(loop, a);
    const int b = match_node(loop);
    const int ra = run_of(pose_index_.at(loop.query));
    const int rb = run_of_place(loop.match);
    run_parent_[std::size_t(std::max(ra, rb))] = std::min(ra, rb);
    int id;
    // A loop the current estimate already agrees with may wait for the next solve; any other
    // one is solved now, through the graph's cost gate.
    Covariance6 measured = loop_covariance(loop, config_.loop_uncertainty);
    const double path = path_m_[pose_index_.at(loop.query)];
    int same_revisit = 1;
    for (auto it = loop_paths_m_.rbegin();
         it != loop_paths_m_.rend() && path - *it < config_.loop_uncertainty.correlation_length_m;
         ++it) {
      ++same_revisit;
    }
    loop_paths_m_.push_back(path);
    measured *= double(same_revisit);
    const Covariance6* covariance = config_.loop_uncertainty.measured ? &measured : nullptr;
    const bool agrees = graph_.loop_residual(a, b, loop.T_query_match, covariance) <=
                        config_.graph.max_loop_residual;
    if (!agrees || described_ - last_solve_at_ >= config_.min_keyframes_between_solves) {
      graph_.add_loop(a, b, loop.T_query_match, &out.solve, &id, covariance);
      ++pose_revision_;
      last_solve_at_ = described_;
      ++times_.solves;
    } else {
      id = graph_.add_loop_unsolved(a, b, loop.T_query_match, covariance);
      unsolved_loops_ = true;
    }
    graph_loops_.push_back({loop_index_.at({loop.query, loop.place_index}), id});
  }
  if (unsolved_loops_ && described_ - last_solve_at_ >= config_.min_keyframes_between_solves) {
    out.solve = graph_.update();
    ++pose_revision_;
    last_solve_at_ = described_;
    unsolved_loops_ = false;
    ++times_.solves;
  }
  update_verdicts(out);
}

// Loops the graph refused or dropped are inconsistent after all; the rest of the graph's are
// accepted (including earlier pending ones this keyframe confirmed).
void LoopCloser::update_verdicts(KeyframeClosure& out) {
  for (const auto& [index, id] : graph_loops_) {
    loops_[index].verdict = graph_.loop_active(id) ? Verdict::Accepted : Verdict::Inconsistent;
  }
  for (Loop& a : out.accepted) a.verdict = loops_[loop_index_.at({a.query, a.place_index})].verdict;
  for (Loop& v : out.verified) {
    const auto it = loop_index_.find({v.query, v.place_index});
    if (it != loop_index_.end()) v.verdict = loops_[it->second].verdict;
  }
}

// The drive ends on the whole graph's solution: online solves were local.
GraphSolve LoopCloser::finish() {
  GraphSolve s;
  if (unsolved_loops_ || graph_.approximate()) {
    const ScopedTimer timer(times_.graph);
    s = graph_.optimise();
    ++pose_revision_;
    unsolved_loops_ = false;
    ++times_.solves;
    KeyframeClosure none;
    update_verdicts(none);
  }
  times_.graph_nodes = graph_.solved_nodes();
  times_.graph_edges = graph_.solved_edges();
  return s;
}

// Temporal consistency of verified loops.
// The loop of an earlier keyframe p (to place mp) predicts this one's: T_q_m =
// T_q_p (odometry) * T_p_mp (its loop) * T_mp_m (the map's odometry).
bool LoopCloser::consistent(const Verified& earlier, const Loop& loop,
                            std::size_t place_index) const {
  const auto map_pose = [&](std::size_t i) { return isometry(*db_.pose(i)).inverse(); };
  if (!db_.pose(place_index) || !db_.pose(earlier.place_index)) return false;
  if (db_.place(place_index).session != db_.place(earlier.place_index).session) return false;
  const Eigen::Isometry3d T_q_p =
      vo_T_world_cam(loop.query).inverse() * vo_T_world_cam(earlier.loop.query);
  const Eigen::Isometry3d T_mp_m = map_pose(earlier.place_index).inverse() * map_pose(place_index);
  const Eigen::Isometry3d predicted = T_q_p * earlier.loop.T_query_match * T_mp_m;
  const Eigen::Isometry3d diff = predicted.inverse() * loop.T_query_match;
  return diff.translation().norm() <= config_.consistency.max_translation_m &&
         rotation_angle(diff.rotation()) <= config_.consistency.max_rotation_deg * M_PI / 180.0;
}

// Keeps the verified loop among the recent ones; returns the loops this confirms (itself and
// the earlier ones it agrees with), or nothing while too few agree.
std::vector<Loop> LoopCloser::confirm(const Loop& loop, std::size_t place_index) {
  while (!recent_.empty() &&
         described_ - recent_.front().described_at >= config_.consistency.window) {
    recent_.pop_front();
  }
  std::vector<Verified*> agreeing;
  for (Verified& v : recent_) {
    if (consistent(v, loop, place_index)) agreeing.push_back(&v);
  }
  recent_.push_back({loop, place_index, described_, false});
  std::vector<Loop> confirmed;
  if (int(agreeing.size()) + 1 < config_.consistency.required) return confirmed;
  agreeing.push_back(&recent_.back());
  for (Verified* v : agreeing) {
    if (v->in_graph) continue;
    v->in_graph = true;
    confirmed.push_back(v->loop);
  }
  return confirmed;
}

// What the closer hands back: corrected poses, the corrected map, re-expressed points.
std::vector<KeyframePose> LoopCloser::corrected_poses(std::size_t first) const {
  std::vector<KeyframePose> out;
  out.reserve(input_poses_.size() - std::min(first, input_poses_.size()));
  for (std::size_t i = first; i < input_poses_.size(); ++i) {
    KeyframePose k;
    k.id = input_poses_[i].id;
    k.T_cam_world = graph_.pose(graph_node_[i]).inverse().matrix().topRows<3>();
    out.push_back(k);
  }
  return out;
}

Database LoopCloser::corrected_map() const {
  Database out(db_.config());
  std::vector<float> payload(std::size_t(db_.payload_floats()));
  for (std::size_t i = 0; i < db_.size(); ++i) {
    const PlaceRef p = db_.place(i);
    std::optional<Pose3x4> pose = db_.pose(i);
    if (p.session == config_.recognition.session) {
      pose = graph_.pose(graph_node_[pose_index_.at(p.keyframe)]).inverse().matrix().topRows<3>();
    }
    db_.stored_payload(i, payload.data());
    out.add_stored(p, payload.data(), db_.frame(i), pose);
  }
  return out;
}

std::vector<IdPoint> reexpress_points(const std::vector<IdPoint>& points,
                                      const std::vector<KeyframePose>& vo_poses,
                                      const std::vector<KeyframePose>& corrected) {
  std::unordered_map<int, Eigen::Isometry3d> correction;  // new T_world_cam * old T_cam_world
  std::unordered_map<int, const KeyframePose*> old;
  for (const KeyframePose& k : vo_poses) old[k.id] = &k;
  for (const KeyframePose& k : corrected) {
    const auto it = old.find(k.id);
    if (it == old.end()) continue;
    correction[k.id] = isometry(k.T_cam_world).inverse() * isometry(it->second->T_cam_world);
  }
  std::vector<IdPoint> out;
  out.reserve(points.size());
  for (const IdPoint& p : points) {
    const auto it = correction.find(p.id);
    if (it == correction.end()) continue;
    IdPoint q = p;
    q.p_world = it->second * p.p_world;
    out.push_back(q);
  }
  return out;
}

}  // namespace loopscan::closure
