#include "loopscan/config/configuration.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "loopscan/core/database/database_checks.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan {
namespace {

// A library validate() message under the name of the file's section it checks.
template <typename Check>
void in_section(const char* section, Check check) {
  try {
    check();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(section) + ": " + e.what());
  }
}

void need(bool ok, const std::string& key, const std::string& what) {
  if (!ok) throw std::invalid_argument(key + ": " + what);
}

}  // namespace

Configuration Configuration::defaults(Method method, Mode mode) {
  Configuration c;
  c.method = method;
  c.mode = mode;
  const SequenceOptions sequence = SequenceOptions::make(method, mode);
  c.imitation = sequence.imitation;
  c.descriptors = sequence.descriptors;
  const eval::PlaceEvaluationOptions evaluation = eval::PlaceEvaluationOptions::make(method, mode);
  c.evaluation.fusion = evaluation.fusion;
  c.evaluation.structure_weight = evaluation.structure_weight;
  c.closure.closer = closure::LoopCloserConfig::make(method, mode);
  c.database.query.candidates = c.closure.closer.recognition.query.candidates;
  if (mode == Mode::Reference) c.baselines.gist = baselines::GistConfig::lear_c();
  return c;
}

Configuration Configuration::defaults(const std::string& method, Mode mode) {
  Method m = Method::ScanContext;
  std::optional<ImageBaseline> image;
  parse_method_name(method, m, image);
  Configuration c = defaults(m, mode);
  c.image_baseline = image;
  return c;
}

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"sc", "m2dp", "delight", "bev", "gist", "bow"};
  return names;
}

std::string method_choices() {
  const std::vector<std::string>& names = method_names();
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  return out;
}

std::string method_name(const Configuration& c) {
  if (c.image_baseline) return *c.image_baseline == ImageBaseline::Gist ? "gist" : "bow";
  return method_name(c.method);
}

void parse_method_name(const std::string& name, Method& method,
                       std::optional<ImageBaseline>& image_baseline) {
  if (name == "gist" || name == "bow") {
    image_baseline = name == "gist" ? ImageBaseline::Gist : ImageBaseline::Bow;
    return;
  }
  try {
    method = parse_method(name);
  } catch (const std::invalid_argument&) {
    std::string message = "unknown method '" + name + "' (expected " + method_choices();
    const std::string guess = io::closest_name(name, method_names());
    if (!guess.empty()) message += "; did you mean '" + guess + "'?";
    throw std::invalid_argument(message + ")");
  }
  image_baseline.reset();
}

SequenceOptions sequence_options(const Configuration& c, Method method) {
  SequenceOptions o = SequenceOptions::make(method, c.mode, c.imitation.range_m);
  // The mode and the range reach every descriptor (make() set them); the rest is the file's.
  o.imitation = c.imitation;
  o.imitation.mode = c.mode;
  const DescriptorConfig shared = o.descriptors;
  o.descriptors = c.descriptors;
  o.descriptors.scan_context.mode = o.descriptors.m2dp.mode = o.descriptors.delight.mode = c.mode;
  o.descriptors.scan_context.max_radius_m = shared.scan_context.max_radius_m;
  o.descriptors.m2dp.max_radius_m = shared.m2dp.max_radius_m;
  return o;
}

SequenceOptions sequence_options(const Configuration& c) { return sequence_options(c, c.method); }

eval::PlaceEvaluationOptions place_evaluation_options(const Configuration& c, Method method,
                                                      bool cross_session) {
  eval::PlaceEvaluationOptions o = eval::PlaceEvaluationOptions::make(method, c.mode);
  o.fusion = c.evaluation.fusion;
  o.structure_weight = c.evaluation.structure_weight;
  o.protocol = cross_session ? c.evaluation.cross_session : c.evaluation.same_session;
  o.birds_eye = c.descriptors.birds_eye;
  o.birds_eye_search = c.birds_eye_search;
  return o;
}

eval::PlaceEvaluationOptions place_evaluation_options(const Configuration& c, bool cross_session) {
  return place_evaluation_options(c, c.method, cross_session);
}

int signature_columns(const Configuration& c) {
  return c.method == Method::BirdsEye ? birds_eye_signature_columns(c.descriptors.birds_eye)
                                      : signature_columns(c.method);
}

DatabaseConfig database_config(const Configuration& c) {
  const DescriptorConfig descriptors = sequence_options(c).descriptors;
  DatabaseConfig d;
  d.method = c.method;
  d.fusion = c.database.fusion;
  d.structure_weight = c.evaluation.structure_weight;
  d.scan_context = descriptors.scan_context;
  d.birds_eye = descriptors.birds_eye;
  d.birds_eye_search = c.birds_eye_search;
  if (c.method == Method::BirdsEye) d.columns = birds_eye_signature_columns(d.birds_eye);
  d.storage = c.database.storage;
  d.mode = c.mode;
  d.frame = descriptor_frame(c.method, descriptors);
  return d;
}

LaneQueryOptions lane_query_options(const Configuration& c) {
  LaneQueryOptions lanes;
  lanes.reverse_window_rad = c.database.lane_reverse_window_deg * M_PI / 180.0;
  lanes.candidates_per_version = c.database.lane_candidates_per_version;
  return lanes;
}

RecognizerConfig recognizer_config(const Configuration& c) {
  RecognizerConfig r;
  const SequenceOptions s = sequence_options(c);
  r.method = c.method;
  r.imitation = s.imitation;
  r.descriptors = s.descriptors;  // describe's, db's and the Recognizer's: one recognition path
  r.database = database_config(c);
  r.query = c.database.query;
  return r;
}

closure::LoopCloserConfig loop_closer_config(const Configuration& c) {
  closure::LoopCloserConfig l = c.closure.closer;
  RecognizerConfig& r = l.recognition;
  const RecognizerConfig file = recognizer_config(c);
  const int exclude_recent = r.query.exclude_recent;  // the closer's own band
  r.method = file.method;
  r.imitation = file.imitation;
  r.descriptors = file.descriptors;
  r.database = file.database;
  r.query = file.query;
  r.query.exclude_recent = exclude_recent;
  return l;
}

baselines::GistConfig gist_config(const Configuration& c) {
  baselines::GistConfig g = c.baselines.gist;
  g.reference = c.mode == Mode::Reference;
  return g;
}

sim::Conditions simulated_conditions(const Configuration& c, sim::Season season) {
  sim::Conditions conditions = sim::Conditions::for_season(season);
  if (c.simulator.illumination_gain) conditions.illumination_gain = *c.simulator.illumination_gain;
  if (c.simulator.gamma) conditions.gamma = *c.simulator.gamma;
  return conditions;
}

void validate_loop_closing(const Configuration& c) {
  need(!c.image_baseline, "method", "loops close with sc, m2dp, delight or bev");
  need(c.imitation.lookahead_m == 0, "imitation.lookahead_m",
       "the loop closer takes forward-only scans (0): it verifies each keyframe as it arrives");
}

void validate(const Configuration& c) {
  if (c.mode == Mode::Reference) {
    need(c.method != Method::BirdsEye, "method",
         "bev (the bird's-eye place) is not the paper's: default mode only");
    // The paper's scan and frame; the file cannot ask reference mode for something else.
    need(c.imitation.lookahead_m == 0, "imitation.lookahead_m",
         "reference mode is the paper's forward-only scan (0)");
    need(c.descriptors.scan_context.frame == DescriptorFrame::Pca &&
             c.descriptors.m2dp.frame == DescriptorFrame::Pca &&
             c.descriptors.delight.frame == DescriptorFrame::Pca,
         "descriptors.*.frame", "reference mode is the paper's PCA frame (pca)");
    need(c.descriptors.scan_context.lateral_versions_m.empty(),
         "descriptors.scan_context.lateral_versions_m",
         "reference mode describes one Scan Context per place ([])");
    need(c.descriptors.scan_context.lateral_offset_m == 0,
         "descriptors.scan_context.lateral_offset_m", "reference mode centres on the keyframe (0)");
  }
  const SequenceOptions s = sequence_options(c);
  in_section("imitation", [&] { validate(s.imitation); });
  in_section("descriptors.scan_context", [&] { validate(s.descriptors.scan_context); });
  in_section("descriptors.m2dp", [&] { validate(s.descriptors.m2dp); });
  in_section("descriptors.delight", [&] { validate(s.descriptors.delight); });
  in_section("descriptors.birds_eye", [&] {
    validate(s.descriptors.birds_eye);
    validate(c.birds_eye_search, s.descriptors.birds_eye);
  });
  need(c.database.fusion != Fusion::Adaptive, "database.fusion",
       "fused, structure or intensity (adaptive fusion needs the whole difference matrix)");
  in_section("database", [&] { validate(database_config(c)); });
  in_section("database.query", [&] { validate(c.database.query, 1); });
  in_section("closure", [&] {
    closure::LoopCloserConfig closer = loop_closer_config(c);
    closer.recognition.imitation.lookahead_m = 0;  // two-sided scans: refused where a closer runs
    closure::validate(closer);
  });
  in_section("simulator.world", [&] { c.simulator.world.validate(); });
  need(c.vo.fixed_keyframes < c.vo.window_keyframes, "vo.fixed_keyframes",
       "fewer than vo.window_keyframes");
  need(c.vo.min_depth_m < c.vo.max_depth_m, "vo.min_depth_m", "below vo.max_depth_m");
  need(c.simulator.vo.min_depth_m < c.simulator.vo.max_depth_m, "simulator.vo.min_depth_m",
       "below simulator.vo.max_depth_m");
}

}  // namespace loopscan
