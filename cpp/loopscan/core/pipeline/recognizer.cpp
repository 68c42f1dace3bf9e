#include "loopscan/core/pipeline/recognizer.hpp"

#include "loopscan/core/pipeline/describe_sequence.hpp"

namespace loopscan {

RecognizerConfig RecognizerConfig::make(Method method, Mode mode, double range_m) {
  const SequenceOptions offline = SequenceOptions::make(method, mode, range_m);
  RecognizerConfig c;
  c.method = method;
  c.imitation = offline.imitation;
  c.descriptors = offline.descriptors;
  c.database.method = method;
  c.database.scan_context = c.descriptors.scan_context;
  c.query.exclude_recent = 99;
  return c;
}

Recognizer::Recognizer(const RecognizerConfig& config)
    : Recognizer(config, Database(config.database)) {}

Recognizer::Recognizer(const RecognizerConfig& config, Database map)
    : config_(config), imitator_(config.imitation), db_(std::move(map)) {}

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
  result.matches = db_.query(place, config_.k, config_.query);
  db_.add({config_.session, ready.keyframe.id}, place, ready.keyframe.T_cam_world);
  return result;
}

}  // namespace loopscan
