#pragma once
// Every tuning parameter of every stage in one value: imitation, descriptors, evaluation and
// fusion, the place database, loop closing, the stereo VO, the simulator and the image
// baselines. Its defaults are the library's own (each stage's make() / config defaults), for a
// method and a mode; the YAML file (config_file.hpp) overrides any subset of them. Commands build
// what each stage takes from it with the functions below, so a value given once reaches every
// stage that shares it (the imitation range is also the descriptors' radius, the mode reaches
// every descriptor).
#include <optional>

#include "loopscan/baselines/gist.hpp"
#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/lane_query.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/lidar_scan.hpp"
#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "loopscan/sim/conditions.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/vo_simulator.hpp"
#include "loopscan/sim/world_config.hpp"
#include "loopscan/vo/vo_config.hpp"

namespace loopscan {

// Offline evaluation (`evaluate`, `run`, `demo`): the fusion of the two halves and the
// ground-truth protocols.
struct EvaluationSettings {
  Fusion fusion = Fusion::Adaptive;  // reference mode: the paper's Fused
  double structure_weight = 2.0;     // w_s
  eval::Protocol same_session = eval::same_session_protocol();
  eval::Protocol cross_session = eval::cross_session_protocol();
};

// The online place database (`db`, the loop closer's map).
struct DatabaseSettings {
  Fusion fusion = Fusion::Fused;  // fused, structure or intensity (adaptive needs whole matrices)
  PlaceStorage storage = PlaceStorage::Full;
  QueryOptions query;  // its retrieval and scoring fields (not sessions, accept, threads)
  // `db query --lanes` (LaneQueryOptions, in degrees here).
  double lane_reverse_window_deg = 20.0;
  int lane_candidates_per_version = LaneQueryOptions{}.candidates_per_version;
};

struct ClosureSettings {
  // What the closer adds to recognition; its `recognition` takes the imitation, descriptor and
  // database sections, but for the fields the file sets under `closure` (the Scan Context frame
  // and lateral versions, and the band of recent places a query skips).
  closure::LoopCloserConfig closer;
  double true_within_m = 10.0;  // with ground truth: a loop is true when its keyframes are closer
  // close, slam: verification and solves on a worker thread (BackgroundLoopCloser), the
  // recording replayed as fast as the worker takes it (WhenFull::Wait); false: one thread.
  bool background = true;
  int queue_capacity = 32;
};

struct OdometryMetricSettings {
  eval::OdometryOptions kitti;  // KITTI's segment lengths, every step_frames-th start
  double rpe_delta_m = 0.5;     // `vo --euroc`: RPE over this path length
};

struct SimulatorSettings {
  sim::WorldConfig world;  // its seed comes from the command line
  sim::VoSimConfig vo;     // its seed and resets come from the command line
  // nullopt: the season's light (sim::Conditions::for_season).
  std::optional<double> illumination_gain, gamma;
  sim::RenderConfig render;  // noise_sigma, max_distance_m, sky_gray
};

struct BaselineSettings {
  baselines::GistConfig gist;  // reference mode: Lear's C GIST (GistConfig::lear_c)
  baselines::OrbConfig orb;
  baselines::VocabularyConfig vocabulary;
};

// The image baselines a configuration may be for instead of a LiDAR-style descriptor.
enum class ImageBaseline { Gist, Bow };

struct Configuration {
  Method method = Method::ScanContext;
  // Set for the image baselines (describe --method gist | bow): the file's `method` then reads
  // gist or bow and `method` above is not used.
  std::optional<ImageBaseline> image_baseline;
  Mode mode = Mode::Default;
  ImitationConfig imitation;
  double reset_jump_m = 5.0;  // default mode without a reset list: detect_vo_resets' jump
  DescriptorConfig descriptors;
  // How bird's-eye places are matched (evaluate's rows, db queries, the Recognizer, loop closing);
  // in the file under descriptors.birds_eye.search.
  BirdsEyeSearchConfig birds_eye_search;
  LidarScanOptions lidar;
  EvaluationSettings evaluation;
  DatabaseSettings database;
  ClosureSettings closure;
  vo::VoConfig vo;
  OdometryMetricSettings odometry_metrics;
  SimulatorSettings simulator;
  BaselineSettings baselines;

  // The library's defaults for a method and a mode.
  static Configuration defaults(Method method = Method::ScanContext, Mode mode = Mode::Default);
  // The same by name: sc | m2dp | delight | bev | gist | bow (parse_method_name).
  static Configuration defaults(const std::string& method, Mode mode);
};

// "sc" | "m2dp" | "delight" | "bev" | "gist" | "bow": the method a configuration (or a described set) is
// for; parse_method_name throws std::invalid_argument on any other name, naming the closest.
std::string method_name(const Configuration& c);
void parse_method_name(const std::string& name, Method& method,
                       std::optional<ImageBaseline>& image_baseline);
const std::vector<std::string>& method_names();  // sc, m2dp, delight, bev, gist, bow
std::string method_choices();  // "sc, m2dp, delight, bev, gist or bow"

// Throws std::invalid_argument naming the first key (as in the file: "closure.candidates") whose
// value is out of its range or contradicts the mode (reference mode is the paper's forward-only
// scan in the PCA frame, one descriptor per place).
void validate(const Configuration& c);

// What loop closing needs beyond validate(): forward-only scans of a LiDAR-style method. Throws
// std::invalid_argument naming the key.
void validate_loop_closing(const Configuration& c);

// What each stage takes. `method` defaults to c.method (run and demo describe with every one).
SequenceOptions sequence_options(const Configuration& c);
SequenceOptions sequence_options(const Configuration& c, Method method);
eval::PlaceEvaluationOptions place_evaluation_options(const Configuration& c, bool cross_session);
eval::PlaceEvaluationOptions place_evaluation_options(const Configuration& c, Method method,
                                                      bool cross_session);
DatabaseConfig database_config(const Configuration& c);
// The width of c.method's signatures as c describes them (bev: its layout's).
int signature_columns(const Configuration& c);
LaneQueryOptions lane_query_options(const Configuration& c);
// A streaming recognizer's: imitation, descriptors, database and query settings (its k, session
// and lane versions keep their defaults).
RecognizerConfig recognizer_config(const Configuration& c);
closure::LoopCloserConfig loop_closer_config(const Configuration& c);
baselines::GistConfig gist_config(const Configuration& c);
// The conditions of a simulated session in `season` (the season's light unless the file sets it).
sim::Conditions simulated_conditions(const Configuration& c, sim::Season season);

}  // namespace loopscan
