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

KeyframeResult Recognizer::add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                        std::size_t n_points, bool reset) {
  KeyframeResult result;
  // 1. Imitate the scan around the keyframe (filtered as the descriptor expects).
  Cloud scan;
  if (!imitator_.next_scan(keyframe, points, n_points, reset, filter_for(config_.method), scan)) {
    return result;
  }
  // 2. Describe it.
  PlaceDescriptor place;
  place.signature = describe(config_.method, scan, config_.descriptors, &place.frame);
  // 3. Query the map, 4. then join it.
  result.described = true;
  result.matches = db_.query(place, config_.k, config_.query);
  db_.add({config_.session, keyframe.id}, place, keyframe.T_cam_world);
  return result;
}

}  // namespace loopscan
