#include "loopscan/core/pipeline/recognizer.hpp"

#include "loopscan/core/database/database_checks.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"

#include <cmath>
#include <stdexcept>

namespace loopscan {

RecognizerConfig RecognizerConfig::make(Method method, Mode mode, double range_m) {
  const SequenceOptions offline = SequenceOptions::make(method, mode, range_m);
  RecognizerConfig c;
  c.method = method;
  c.imitation = offline.imitation;
  c.descriptors = offline.descriptors;
  c.database.method = method;
  c.database.scan_context = c.descriptors.scan_context;
  c.database.birds_eye = c.descriptors.birds_eye;
  c.query.exclude_recent = 99;
  return c;
}

DatabaseConfig map_config(const RecognizerConfig& config) {
  DatabaseConfig d = config.database;
  d.method = config.method;
  d.mode = config.imitation.mode;
  d.frame = descriptor_frame(config.method, config.descriptors);
  return d;
}

Recognizer::Recognizer(const RecognizerConfig& config)
    : Recognizer(config, Database(map_config(config))) {}

Recognizer::Recognizer(const RecognizerConfig& config, Database map)
    : config_(config), imitator_(config.imitation), db_(std::move(map)) {
  require_same_description(db_.config(), map_config(config), "Recognizer");
  if (config.method == Method::BirdsEye) db_.set_birds_eye_search(config.database.birds_eye_search);
  if (config.lane_offset_m != 0 &&
      (config.method != Method::ScanContext ||
       config.descriptors.scan_context.frame != DescriptorFrame::Camera ||
       config.descriptors.scan_context.mode != Mode::Default)) {
    throw std::invalid_argument(
        "RecognizerConfig: lane_offset_m needs Scan Context in the camera frame (default mode)");
  }
  if (!(std::abs(config.lane_offset_m) <= 100.0)) {
    throw std::invalid_argument("RecognizerConfig: lane_offset_m must be finite, |x| <= 100 m");
  }
}

std::vector<KeyframeResult> Recognizer::add_keyframe(const KeyframePose& keyframe,
                                                     const IdPoint* points, std::size_t n_points,
                                                     bool reset) {
  // 1. Imitate the scans that are ready (filtered as the descriptor expects).
  ready_.clear();
  imitator_.push(keyframe, points, n_points, reset, filter_for(config_.method), ready_);
  std::vector<KeyframeResult> out;
  for (const ReadyScan& r : ready_) out.push_back(recognise(r));
  return out;
}

std::vector<KeyframeResult> Recognizer::finish() {
  ready_.clear();
  imitator_.finish(filter_for(config_.method), ready_);
  std::vector<KeyframeResult> out;
  for (const ReadyScan& r : ready_) out.push_back(recognise(r));
  return out;
}

KeyframeResult Recognizer::recognise(const ReadyScan& ready) {
  KeyframeResult result;
  // 2. Describe the scan.
  PlaceDescriptor place;
  place.signature = describe(config_.method, ready.scan, config_.descriptors, &place.frame);
  // 3. Query the map, 4. then join it.
  result.keyframe = ready.keyframe.id;
  std::vector<PlaceDescriptor> versions;
  if (config_.lane_offset_m != 0) {
    for (const double side : {-1.0, 1.0}) {
      DescriptorConfig shifted = config_.descriptors;
      shifted.scan_context.lateral_offset_m = side * config_.lane_offset_m;
      PlaceDescriptor v;
      v.signature = describe(config_.method, ready.scan, shifted, &v.frame);
      versions.push_back(std::move(v));
    }
  }
  result.matches =
      query_with_lane_versions(db_, place, versions, config_.k, config_.query, config_.lanes);
  db_.add({config_.session, ready.keyframe.id}, place, ready.keyframe.T_cam_world);
  return result;
}

}  // namespace loopscan
