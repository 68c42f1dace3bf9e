#pragma once
// The keys of the configuration file, in one place: each names a field of Configuration, its
// range and a one-line description. Reading a file, writing the defaults and the docs' table all
// walk this list, so they cannot drift apart.
//
// A visitor V provides:
//   void section(const char* name, const char* doc, F body)  -- a nested map; body() visits it
//   void key(const char* name, T& value, const Range& range, const char* doc)   numbers
//   void key(const char* name, T& value, const char* doc)                       bools, enums
//   void method_key(const char* name, Configuration& c, const char* doc)         the method
#include <cmath>
#include <limits>
#include <string>

#include "loopscan/config/configuration.hpp"

namespace loopscan::config_keys {

// The values a number may take: [lo, hi], or (lo, hi] when lo_open. For lists: each element.
// max_items bounds a list's length.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  std::size_t max_items = 64;
};

inline Range closed(double lo, double hi) { return {lo, hi, false}; }
inline Range above(double lo, double hi) { return {lo, hi, true}; }  // (lo, hi]
inline Range list(double lo, double hi, std::size_t max_items, bool lo_open = false) {
  return {lo, hi, lo_open, max_items};
}
constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename V>
void visit_imitation(V& v, Configuration& c) {
  ImitationConfig& m = c.imitation;
  v.key("range_m", m.range_m, closed(0.1, 1000),
        "range of the imitated LiDAR scan (m); also Scan Context's and M2DP's radius");
  v.key("init_frames", m.init_frames, closed(0, 100000),
        "keyframes after a VO reset that only accumulate points (no place)");
  v.key("voxel_divisions_xz", m.voxel_divisions_xz, closed(1, 10000),
        "Cartesian filter (Scan Context): voxel = range / this along x and z");
  v.key("voxel_divisions_y", m.voxel_divisions_y, closed(1, 10000),
        "... and range / this along y (the camera's down axis)");
  v.key("polar_resolution_deg", m.polar_resolution_deg, closed(0.05, 90),
        "polar filter (M2DP, DELIGHT): cell size in azimuth and elevation (degrees)");
  v.key("lookahead_m", m.lookahead_m, closed(0, 1000),
        "two-sided scans: describe a keyframe once the VO is this far past it (0: the paper's "
        "forward-only scan; default mode only; not with the loop closer)");
  v.key("reset_jump_m", c.reset_jump_m, above(0, 1e6),
        "default mode without a reset list: a keyframe within 1 m of the VO origin after a jump "
        "longer than this is a VO reset");
}

// The descriptors' sizes (Scan Context 20 x 60 bins, M2DP 4 x 16 planes of 8 x 16 bins,
// DELIGHT 256 gray levels) are not keys: they are the layout of the signature files every
// reader checks, the paper's; the library's configs take others.
template <typename V>
void visit_descriptors(V& v, Configuration& c) {
  DescriptorConfig& d = c.descriptors;
  v.section("scan_context", "Scan Context (structure and intensity halves)", [&] {
    ScanContextConfig& s = d.scan_context;
    v.key("frame", s.frame,
          "pca (the paper's) | camera (keyframe-centred, yaw left to the sector search) | "
          "centroid | gravity-pca");
    v.key("lateral_offset_m", s.lateral_offset_m, closed(-100, 100),
          "camera frame: centre the descriptor this far right of the keyframe");
    v.key("lateral_versions_m", s.lateral_versions_m,
          list(-100, 100, ScanContextConfig::kMaxLateralVersions),
          "extra rows centred this far right (camera or centroid frame, default mode); a query "
          "matches a place with its best row");
    v.key("max_height", s.max_height,
          "bin value: the highest point above the ground (Scan Context's own, for real LiDAR) "
          "instead of the paper's height range");
    v.key("sensor_height_m", s.sensor_height_m, closed(-100, 100),
          "max_height: the sensor's height above the ground (m)");
  });
  v.section("m2dp", "M2DP", [&] {
    v.key("frame", d.m2dp.frame, "pca (the paper's) | gravity-pca | camera | centroid");
  });
  v.section("delight", "DELIGHT", [&] {
    DelightConfig& l = d.delight;
    v.key("inner_radius_m", l.inner_radius_m, closed(0, 1000),
          "radius of the inner half of the 16 regions (m)");
    v.key("frame", l.frame, "pca (the paper's) | gravity-pca | camera | centroid");
  });
  v.section("birds_eye", "the bird's-eye place (bev; default mode): image, key and search", [&] {
    BirdsEyePlaceConfig& b = d.birds_eye;
    v.key("cell", b.cell,
          "density (points seen in a cell; the better within a season) | height (of its highest "
          "point; the better across seasons)");
    v.key("cell_m", b.cell_m, closed(0.05, 10), "image cell (m)");
    v.key("range_m", b.range_m, closed(1, 200), "the image spans [-range_m, range_m] in x and z");
    v.key("taper_start_m", b.taper_start_m, closed(0, 400),
          "cell weights fall smoothly from 1 here to 0 at taper_end_m (m from the keyframe)");
    v.key("taper_end_m", b.taper_end_m, closed(0, 400), "the image's radius (m)");
    v.key("rings", b.rings, closed(1, 256), "key radii");
    v.key("angles", b.angles, closed(2, 720), "key angles over [0, pi): the key's yaw resolution");
    v.section("search", "matching: key ranking, then an image search of the finalists", [&] {
      BirdsEyeSearchConfig& f = c.birds_eye_search;
      v.key("finalists", f.finalists, closed(1, 1000),
            "places ranked by key whose images are searched (each ~200x a key match)");
      v.key("max_shift_m", f.max_shift_m, closed(0, 400), "searched in x and z (m)");
      v.key("yaw_steps", f.yaw_steps, closed(0, 360),
            "extra yaws each side of the key's, one key angle apart");
      v.key("coarse_cells", f.coarse_cells, closed(1, 16),
            "shifts first searched on cells merged this many a side (1: every shift in full)");
      v.key("refined_peaks", f.refined_peaks, closed(1, 100),
            "coarse peaks searched again at full resolution");
      v.key("pose_window_start_m", f.pose_window_start_m, closed(0, 400),
            "the pose is searched on images weighed from 1 here to 0 at pose_window_end_m, and "
            "scored on the images as stored");
      v.key("pose_window_end_m", f.pose_window_end_m, closed(0, 400), "(m from the keyframe)");
    });
  });
}

template <typename V>
void visit_evaluation(V& v, Configuration& c) {
  EvaluationSettings& e = c.evaluation;
  v.key("fusion", e.fusion,
        "adaptive (row and global z-scores, weights from the halves' agreement) | fused (the "
        "paper's Eq. 1) | structure | intensity; `evaluate --fusion` overrides it");
  v.key("structure_weight", e.structure_weight, closed(0, 1000),
        "w_s in w_s z(structure) + z(intensity), offline and in the database");
  const auto protocol = [&v](eval::Protocol& p) {
    v.key("threshold_m", p.threshold_m, above(0, 1e6),
          "a query is a revisit when a place lies closer than this (m)");
    v.key("mask", p.mask_width, closed(0, 1e9), "places with |i - j| < mask are left out");
  };
  v.section("same_session", "a sequence matched with itself (KITTI protocol)",
            [&] { protocol(e.same_session); });
  v.section("cross_session", "queries against another session's places (RobotCar protocol)",
            [&] { protocol(e.cross_session); });
}

template <typename V>
void visit_database(V& v, Configuration& c) {
  DatabaseSettings& d = c.database;
  v.key("fusion", d.fusion, "fused | structure | intensity (each query fused on its own)");
  v.key("storage", d.storage,
        "full | compact (Scan Context: a byte per spectrum value, ~2.9 KB a place instead of "
        "~10 KB)");
  v.section("query", "retrieval", [&] {
    QueryOptions& q = d.query;
    v.key("retrieval", q.retrieval, "indexed | exact (`db query --exact`)");
    v.key("candidates", q.candidates, closed(1, 1e6), "index candidates scored exactly");
    v.key("index_pool_factor", q.index_pool_factor, closed(1, 1000),
          "Scan Context: places the coarse key scan hands to re-ranking, per candidate");
    v.key("stats_sample", q.stats_sample, closed(2, 1e6),
          "indexed fused scores: places sampled for the row's mean and deviation");
    v.key("refine", q.refine, closed(0, 1e6),
          "Scan Context with lateral versions: best candidates scored with every version "
          "(0: all)");
    v.key("exclude_recent", q.exclude_recent, closed(0, 1e9), "ignore the N places added last");
    v.key("uniqueness_ratio", q.uniqueness_ratio, closed(0, 1),
          "keep the best only if the next distinct place is this much less good (1: off)");
    v.key("distinct_gap", q.distinct_gap, closed(0, 1e9),
          "uniqueness: another session, or more than this many keyframes away");
    v.key("max_distance", q.max_distance, closed(-kInf, kInf),
          "drop results farther than this (.inf: none)");
  });
  v.section("lanes", "`db query --lanes`: versions from the neighbouring lanes", [&] {
    v.key("reverse_window_deg", d.lane_reverse_window_deg, above(0, 180),
          "a lane version's match counts when its yaw is within this of 180 degrees");
    v.key("candidates_per_version", d.lane_candidates_per_version, closed(1, 1e6),
          "best places of each lane version checked");
  });
}

template <typename V>
void visit_closure(V& v, Configuration& c) {
  closure::LoopCloserConfig& l = c.closure.closer;
  v.key("candidates", l.candidates, closed(1, 100), "places verified per keyframe");
  v.key("max_candidate_distance", l.max_candidate_distance, closed(-kInf, kInf),
        "candidates with a descriptor distance above this are not verified (fused z-score; "
        ".inf: all)");
  v.key("min_keyframes_between_solves", l.min_keyframes_between_solves, closed(0, 1e9),
        "loops the estimate already agrees with wait this long for a solve");
  v.key("exclude_recent", l.recognition.query.exclude_recent, closed(0, 1e9),
        "a query skips the places of the last N keyframes (the paper's 100-place mask)");
  v.key("true_within_m", c.closure.true_within_m, above(0, 1000),
        "with ground truth: a loop is true when its keyframes are this close (m)");
  v.key("threads", l.threads, closed(1, 256),
        "threads for each candidate's alignments and the plane fits (the same results)");
  v.section("background", "close, slam: verification and graph solves on a worker thread", [&] {
    v.key("enabled", c.closure.background, "false: everything on the caller's thread");
    v.key("queue_capacity", c.closure.queue_capacity, closed(1, 1e5),
          "keyframes waiting for the worker; the reader waits beyond this");
  });
  v.section("cloud", "each place's cloud for verification", [&] {
    v.key("voxel_m", l.cloud.voxel_m, closed(0.01, 10), "one point (the centroid) per voxel");
    v.key("max_points", l.cloud.max_points, closed(16, 1 << 22), "kept evenly beyond this");
    v.key("max_range_m", l.cloud.max_range_m, above(0, 1000), "farther points are dropped");
    v.key("max_unclassified_places", l.cloud.max_unclassified_places, closed(0, 1 << 24),
          "places kept as voxel clouds until a verification classifies them; beyond, the "
          "oldest is classified (0: each at once)");
  });
  v.section("normals", "surface normals of the query cloud", [&] {
    v.key("neighbours", l.normals.neighbours, closed(3, 1000), "points of a plane fit");
    v.key("max_radius_m", l.normals.max_radius_m, above(0, 1000),
          "neighbours farther away are not used");
    v.key("max_planarity", l.normals.max_planarity, closed(0, 1),
          "smallest / middle eigenvalue above this: no plane, no normal");
  });
  v.section("verification", "geometric verification of a candidate", [&] {
    closure::VerifyConfig& f = l.verify;
    v.key("min_points", f.min_points, closed(3, 1 << 22), "in each cloud");
    v.key("min_overlap", f.min_overlap, closed(0, 1),
          "share of the place's structure points within the inlier distance of the query's");
    v.key("along_track_seed_m", f.along_track_seed_m, closed(0, 100),
          "ICP also starts this far ahead and behind the query (nearby: unless birds_eye)");
    v.key("screen_iterations", f.screen_iterations, closed(1, 1000),
          "at most this many coarse ICP iterations for every start");
    v.key("screen_min_overlap", f.screen_min_overlap, closed(0, 1),
          "below this after screening: refused without refining");
    v.key("rival_share", f.rival_share, closed(0, 1),
          "a rival start is refined when it screened this close to the best");
    v.key("ambiguity_share", f.ambiguity_share, closed(0, 1),
          "a refined rival this close to the best's overlap: ambiguous, refused");
    v.key("rival_place_share", f.rival_place_share, closed(0, 10),
          "another candidate place aligned to this share of the accepted one's overlap ...");
    v.key("rival_place_m", f.rival_place_m, closed(0, 1000),
          "... that puts the query this far from where it does: ambiguous (0: off)");
    v.key("slide_shift_m", f.slide_shift_m, above(0, 100),
          "the place's near structure moved this far and 1.5 times it along the track ...");
    v.key("slide_near_m", f.slide_near_m, above(0, 1000), "... near: this close to the query ...");
    v.key("slide_share", f.slide_share, closed(0, 10),
          "... fitting this share as well as aligned: slid, ambiguous (0: off)");
    v.key("max_rmse_m", f.max_rmse_m, above(0, 100), "point-to-plane RMS of the inliers");
    v.key("min_translation_constraint", f.min_translation_constraint, closed(0, 1),
          "weakest translation direction (smallest eigenvalue of sum n n^T per inlier)");
    v.key("max_translation_m", f.max_translation_m, above(0, 1000),
          "farther apart is not the same place");
    v.section("birds_eye", "a bird's-eye (x, z, yaw) search that seeds a nearby place's ICP", [&] {
      closure::BirdsEyeConfig& b = f.birds_eye;
      v.key("enabled", b.enabled, "off by default: two false loops on one drive (docs/loop-closing.md)");
      v.key("cell_m", b.cell_m, closed(0.1, 10), "grid cell");
      v.key("max_range_m", b.max_range_m, above(0, 200), "points farther from their keyframe are left out");
      v.key("max_shift_m", b.max_shift_m, closed(0, 50), "searched around each guess in x and z");
      v.key("yaw_window_deg", b.yaw_window_deg, closed(0, 180), "searched around each guess's yaw");
      v.key("yaw_step_deg", b.yaw_step_deg, closed(0.1, 90), "");
      v.key("peaks", b.peaks, closed(1, 100), "distinct poses that seed ICP");
      v.key("separation_m", b.separation_m, closed(0, 100), "poses nearer than this ...");
      v.key("separation_deg", b.separation_deg, closed(0, 180), "... and this are one");
    });
    v.section("icp", "robust point-to-plane ICP", [&] {
      closure::IcpConfig& i = f.icp;
      v.key("stage_distances_m", i.stage_distances_m, list(0, 100, 16, true),
            "correspondence distance of each stage, coarse to fine");
      v.key("stage_strides", i.stage_strides, list(1, 1000, 16),
            "every n-th source point in each stage");
      v.key("max_iterations_per_stage", i.max_iterations_per_stage, closed(1, 1000), "");
      v.key("converged_translation_m", i.converged_translation_m, above(0, 100),
            "a step below both ends the stage");
      v.key("converged_rotation_rad", i.converged_rotation_rad, above(0, M_PI), "");
      v.key("inlier_distance_m", i.inlier_distance_m, above(0, 100), "for overlap and RMS");
    });
  });
  v.section("consistency", "a verified loop waits for agreeing neighbours", [&] {
    closure::ConsistencyConfig& k = l.consistency;
    v.key("required", k.required, closed(1, 100), "verified loops that agree, this one included");
    v.key("window", k.window, closed(1, 1000), "... among the last this many described keyframes");
    v.key("max_translation_m", k.max_translation_m, above(0, 1e6), "agreement in translation");
    v.key("max_rotation_deg", k.max_rotation_deg, above(0, 360), "agreement in rotation");
  });
  v.section("proximity", "places near the query in the current trajectory estimate", [&] {
    closure::ProximityConfig& p = l.proximity;
    v.key("candidates", p.candidates, closed(0, 100),
          "nearest places verified per keyframe (0: off)");
    v.key("base_radius_m", p.base_radius_m, closed(0, 1e4),
          "search radius after a loop or at a run's start");
    v.key("radius_per_m", p.radius_per_m, closed(0, 10),
          "... growing with the path travelled since (m/m)");
    v.key("max_radius_m", p.max_radius_m, closed(0, 1e4), "");
    v.key("min_overlap", p.min_overlap, closed(0, 1), "verification.min_overlap for these places");
  });
  v.section("lifelong", "a keyframe whose place the map holds links to it, not a copy", [&] {
    closure::LifelongConfig& f = l.lifelong;
    v.key("enabled", f.enabled, "held: an accepted loop to a place of its own session within");
    v.key("max_distance_m", f.max_distance_m, closed(0, 1e3), "... this distance (m)");
    v.key("max_rotation_deg", f.max_rotation_deg, closed(0, 180), "... and rotation (degrees)");
    v.key("merge_nodes", f.merge_nodes, "its pose-graph node merges into the place's ...");
    v.key("merge_after_keyframes", f.merge_after_keyframes, closed(1, 1000000),
          "... this many described keyframes later");
  });
  v.section("loop_uncertainty", "each loop edge's covariance, from its alignment", [&] {
    closure::LoopUncertaintyConfig& u = l.loop_uncertainty;
    v.key("measured", u.measured, "false: every loop gets pose_graph.loop_translation_m / _deg");
    v.key("base_m", u.base_m, above(0, 1000), "same place, same heading (m)");
    v.key("reverse_along_m", u.reverse_along_m, closed(0, 1000),
          "added along the track for the opposite heading (m)");
    v.key("lateral_per_m", u.lateral_per_m, closed(0, 1000),
          "added across the track per metre between the keyframes");
    v.key("turn_m", u.turn_m, closed(0, 1000), "added across the track at 90 degrees of heading");
    v.key("geometry_m", u.geometry_m, closed(0, 1000),
          "scaled by 1 / sqrt(3 lambda) in each direction the surfaces constrain (lambda)");
    v.key("rotation_deg", u.rotation_deg, above(0, 1000), "");
    v.key("correlation_length_m", u.correlation_length_m, closed(0, 1000),
          "the k-th loop within this much travel gets k times the covariance");
  });
  v.section("pose_graph", "the SE(3) pose graph (Ceres)", [&] {
    closure::PoseGraphConfig& g = l.graph;
    v.key("odometry_translation_per_m", g.odometry_translation_per_m, above(0, 1e6),
          "VO translation sigma per metre travelled (m/m)");
    v.key("odometry_translation_min_m", g.odometry_translation_min_m, above(0, 1e6), "");
    v.key("odometry_rotation_deg_per_m", g.odometry_rotation_deg_per_m, above(0, 1e6),
          "VO rotation sigma per metre travelled (deg/m)");
    v.key("odometry_rotation_min_deg", g.odometry_rotation_min_deg, above(0, 1e6), "");
    v.key("loop_translation_m", g.loop_translation_m, above(0, 1e6),
          "loop edge sigma without loop_uncertainty.measured");
    v.key("loop_rotation_deg", g.loop_rotation_deg, above(0, 1e6), "");
    v.key("max_loop_cost", g.max_loop_cost, above(0, 1e12),
          "a loop may raise the optimised cost by at most this (chi-square, 6 dof)");
    v.key("max_loop_residual", g.max_loop_residual, above(0, 1e12),
          "loops whose whitened residual exceeds this are dropped");
    v.key("max_iterations", g.max_iterations, closed(1, 10000), "per solve");
    v.key("incremental", g.incremental,
          "online solves move only the nodes near what changed (false: the whole graph)");
    v.key("window_nodes", g.window_nodes, closed(1, 100000000),
          "the first window of a local solve (nodes nearest to what changed)");
    v.key("max_border_strain", g.max_border_strain, above(0, 1e6),
          "the window grows 4x while an edge across its border changed its whitened residual by "
          "more");
    v.key("coarse_nodes", g.coarse_nodes, closed(0, 100000000),
          "a window larger than coarse_above_nodes becomes a coarse whole-graph solve over about "
          "this many nodes (0: never)");
    v.key("coarse_above_nodes", g.coarse_above_nodes, closed(1, 100000000), "");
  });
}

template <typename V>
void visit_vo(V& v, Configuration& c) {
  vo::VoConfig& o = c.vo;
  v.key("grid_cols", o.grid_cols, closed(1, 1000), "corners: one FAST corner per grid cell");
  v.key("grid_rows", o.grid_rows, closed(1, 1000), "");
  v.key("fast_threshold", o.fast_threshold, closed(1, 255), "");
  v.key("klt_window_px", o.klt_window_px, closed(3, 255), "Lucas-Kanade window");
  v.key("klt_levels", o.klt_levels, closed(0, 10), "pyramid levels");
  v.key("forward_backward_px", o.forward_backward_px, above(0, 100), "track check");
  v.key("ransac_reprojection_px", o.ransac_reprojection_px, above(0, 100), "P3P RANSAC");
  v.key("ransac_iterations", o.ransac_iterations, closed(1, 1e6), "");
  v.key("track_sigma_px", o.track_sigma_px, above(0, 100), "pose weights: tracking noise");
  v.key("stereo_sigma_px", o.stereo_sigma_px, closed(0, 100),
        "... and disparity noise (0: no depth uncertainty)");
  v.key("min_inliers", o.min_inliers, closed(4, 1e6), "fewer: the VO resets");
  v.key("max_step_m", o.max_step_m, above(0, 1e6), "a larger jump between frames: reset");
  v.key("stereo_half_window", o.stereo_half_window, closed(1, 10), "SAD window half size (px)");
  v.key("stereo_uniqueness", o.stereo_uniqueness, above(0, 1), "best cost < this * second best");
  v.key("min_depth_m", o.min_depth_m, above(0, 1e4), "stereo depths kept");
  v.key("max_depth_m", o.max_depth_m, above(0, 1e4), "");
  v.key("keyframe_distance_m", o.keyframe_distance_m, above(0, 1e4), "a keyframe every ...");
  v.key("keyframe_rotation_deg", o.keyframe_rotation_deg, above(0, 360), "... or this turn");
  v.key("keyframe_min_track_ratio", o.keyframe_min_track_ratio, closed(0, 1),
        "... or when fewer of the keyframe's tracks survive");
  v.key("window_keyframes", o.window_keyframes, closed(2, 100), "bundle adjustment window");
  v.key("fixed_keyframes", o.fixed_keyframes, closed(1, 99), "oldest keyframes held fixed");
  v.key("ba_iterations", o.ba_iterations, closed(1, 1000), "");
  v.key("ba_huber_px", o.ba_huber_px, above(0, 100), "");
  v.key("ba_on_worker", o.ba_on_worker,
        "bundle adjustment on a worker thread (the same trajectory either way)");
  v.key("points_per_keyframe", o.points_per_keyframe, closed(1, 100000),
        "exported DSO-like points");
  v.key("point_min_gradient", o.point_min_gradient, closed(0, 255), "");
  v.key("point_gradient_over_median", o.point_gradient_over_median, closed(0, 255),
        "DSO's setting_minGradHistAdd");
  v.key("point_max_depth_m", o.point_max_depth_m, above(0, 1e4), "");
}

template <typename V>
void visit_simulator(V& v, Configuration& c) {
  SimulatorSettings& s = c.simulator;
  v.section("world", "the synthetic city (its seed is `--seed`)", [&] {
    sim::WorldConfig& w = s.world;
    v.key("road_half_width_m", w.road_half_width_m, closed(0, 1000), "nothing but ground here");
    v.key("camera_height_m", w.camera_height_m, above(0, 100), "");
    v.key("sidewalk_width_m", w.sidewalk_width_m, above(0, 100), "");
    v.key("road_grain", w.road_grain, closed(0, 1), "asphalt texture amplitude");
    v.key("lane_markings", w.lane_markings, "dashed lane lines, solid edge lines");
    v.key("lane_width_m", w.lane_width_m, above(0, 100), "");
    v.key("guard_rails", w.guard_rails, "along both road edges");
    v.key("guard_rail_offset_m", w.guard_rail_offset_m, closed(0, 100), "beyond the road edge");
    v.key("sample_spacing_m", w.sample_spacing_m, above(0, 1000), "");
    v.key("revisit_radius_m", w.revisit_radius_m, above(0, 1000), "");
    v.key("facade_width_min_m", w.facade_width_min_m, above(0, 1000), "");
    v.key("facade_width_max_m", w.facade_width_max_m, above(0, 1000), "");
    v.key("facade_height_min_m", w.facade_height_min_m, above(0, 1000), "");
    v.key("facade_height_max_m", w.facade_height_max_m, above(0, 1000), "");
    v.key("facade_depth_min_m", w.facade_depth_min_m, above(0, 1000), "");
    v.key("facade_depth_max_m", w.facade_depth_max_m, above(0, 1000), "");
    v.key("setback_min_m", w.setback_min_m, closed(0, 1000), "beyond the sidewalk");
    v.key("setback_max_m", w.setback_max_m, closed(0, 1000), "");
    v.key("gap_probability", w.gap_probability, closed(0, 0.999), "");
    v.key("gap_width_min_m", w.gap_width_min_m, above(0, 1000), "");
    v.key("gap_width_max_m", w.gap_width_max_m, above(0, 1000), "");
    v.key("tree_street_probability", w.tree_street_probability, closed(0, 1), "");
    v.key("tree_spacing_min_m", w.tree_spacing_min_m, above(0, 1000), "");
    v.key("tree_spacing_max_m", w.tree_spacing_max_m, above(0, 1000), "");
    v.key("crown_radius_min_m", w.crown_radius_min_m, above(0, 100), "");
    v.key("crown_radius_max_m", w.crown_radius_max_m, above(0, 100), "");
    v.key("foliage_voxel_m", w.foliage_voxel_m, above(0, 10), "");
    v.key("pole_spacing_m", w.pole_spacing_m, above(0, 1000), "");
    v.key("car_slot_spacing_m", w.car_slot_spacing_m, above(0, 1000), "");
    v.key("car_occupancy", w.car_occupancy, closed(0, 1), "redrawn per session");
    v.key("grid_cell_m", w.grid_cell_m, above(0, 1000), "ray-casting grid");
    v.key("max_route_length_m", w.max_route_length_m, above(0, 1e7), "");
    v.key("max_extent_m", w.max_extent_m, above(0, 1e7), "");
  });
  v.section("vo", "the simulated VO's output (its seed follows `--seed` and `--session`)", [&] {
    sim::VoSimConfig& o = s.vo;
    v.key("points_per_keyframe", o.points_per_keyframe, closed(1, 100000), "SO-DSO-like density");
    v.key("max_rays_per_keyframe", o.max_rays_per_keyframe, closed(1, 1e7), "");
    v.key("min_depth_m", o.min_depth_m, above(0, 1e4), "");
    v.key("max_depth_m", o.max_depth_m, above(0, 1e4), "");
    v.key("disparity_sigma_px", o.disparity_sigma_px, closed(0, 100), "stereo noise");
    v.key("gradient_threshold", o.gradient_threshold, above(0, 1e6),
          "a pixel is kept with probability min(1, gradient / this)");
    v.key("gray_noise", o.gray_noise, closed(0, 255), "gray levels");
    v.key("drift_translation_per_m", o.drift_translation_per_m, closed(0, 1),
          "VO drift, m per m travelled");
    v.key("drift_rotation_deg_per_m", o.drift_rotation_deg_per_m, closed(0, 90),
          "VO drift, degrees per m travelled");
  });
  v.section("illumination", "null: the season's light", [&] {
    v.key("gain", s.illumination_gain, closed(0, 100), "gray = 255 (gain albedo)^gamma");
    v.key("gamma", s.gamma, closed(0.01, 10), "");
  });
  v.section("render", "`render`: rectified stereo images", [&] {
    v.key("noise_sigma", s.render.noise_sigma, closed(0, 255), "sensor noise, gray levels");
    v.key("max_distance_m", s.render.max_distance_m, above(0, 1e5), "farther: sky");
    v.key("sky_gray", s.render.sky_gray, closed(0, 255), "at the horizon");
  });
}

template <typename V>
void visit_baselines(V& v, Configuration& c) {
  BaselineSettings& b = c.baselines;
  v.section("gist", "GIST (reference mode: Lear's C GIST)", [&] {
    v.key("image_size", b.gist.image_size, closed(8, 4096), "the image is resized to this square");
    v.key("scales", b.gist.scales, closed(1, 16), "");
    v.key("orientations", b.gist.orientations, closed(1, 64), "");
    v.key("grid", b.gist.grid, closed(1, 64), "cells per side");
    v.key("boundary", b.gist.boundary, closed(0, 1024), "mirrored border (px)");
    v.key("prefilter_fc", b.gist.prefilter_fc, above(0, 1000), "cycles per image");
  });
  v.section("orb", "ORB features of BoW", [&] {
    v.key("features", b.orb.features, closed(1, 100000), "per image");
    v.key("scale_factor", b.orb.scale_factor, above(1, 10), "");
    v.key("levels", b.orb.levels, closed(1, 32), "");
    v.key("fast_threshold", b.orb.fast_threshold, closed(1, 255), "");
  });
  v.section("vocabulary", "`vocab train`", [&] {
    v.key("branching", b.vocabulary.branching, closed(2, 1000), "k");
    v.key("depth", b.vocabulary.depth, closed(1, 10), "levels L");
    v.key("iterations", b.vocabulary.iterations, closed(1, 1000), "k-majority rounds per node");
    v.key("seed", b.vocabulary.seed, closed(0, 4294967295.0), "clustering seed");
  });
}

// Every key of the file, in the order `loopscan config` prints them.
template <typename V>
void visit(V& v, Configuration& c) {
  v.method_key("method", c,
               "sc | m2dp | delight (| gist | bow: the image baselines) of describe, evaluate, "
               "db, close, slam (run and demo use every method)");
  v.key("mode", c.mode,
        "default (the paper's defects fixed, faster) | reference (the paper's code, bit for bit)");
  v.section("imitation", "the imitated LiDAR scan around each keyframe",
            [&] { visit_imitation(v, c); });
  v.section("descriptors", "describe: the place descriptors", [&] { visit_descriptors(v, c); });
  v.section("lidar", "describe --lidar: real LiDAR scans", [&] {
    v.key("reflectance_scale", c.lidar.reflectance_scale, closed(0, 1e6),
          "gray = reflectance * this; 0: 255 when every reflectance is <= 1, else 1");
  });
  v.section("evaluation", "evaluate, run, demo: fusion and ground truth",
            [&] { visit_evaluation(v, c); });
  v.section("database", "db build / query: the place database", [&] { visit_database(v, c); });
  v.section("closure", "close, slam: loop closing", [&] { visit_closure(v, c); });
  v.section("vo", "vo, run, slam: the stereo VO", [&] { visit_vo(v, c); });
  v.section("odometry_metrics", "vo, run, slam: accuracy against ground truth", [&] {
    v.key("segment_lengths_m", c.odometry_metrics.kitti.segment_lengths_m, list(0, 1e6, 64, true),
          "KITTI's relative error over these segment lengths (m)");
    v.key("step_frames", c.odometry_metrics.kitti.step_frames, closed(1, 1e6),
          "a segment starts every this many frames");
    v.key("rpe_delta_m", c.odometry_metrics.rpe_delta_m, above(0, 1e6),
          "vo --euroc: RPE over this path length (m)");
  });
  v.section("simulator", "simulate, render, demo", [&] { visit_simulator(v, c); });
  v.section("baselines", "the image baselines", [&] { visit_baselines(v, c); });
}

}  // namespace loopscan::config_keys
