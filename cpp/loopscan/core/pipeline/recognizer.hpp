#pragma once
// Streaming place recognition: feed keyframes and their points as the VO exports them; each
// keyframe that gets an imitated scan is described, queried against the map so far and then
// added to it. Loop candidates come back as soon as they exist.
#include <vector>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/lane_query.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"

namespace loopscan {

struct RecognizerConfig {
  Method method = Method::ScanContext;
  ImitationConfig imitation;
  DescriptorConfig descriptors;
  DatabaseConfig database;
  QueryOptions query;  // default: skip the 99 places added last (the paper's 100-place mask)
  int k = 1;
  int session = 0;  // session of the places this recognizer adds
  // Reverse drives in the other lane (Scan Context in the camera frame only): each place is
  // also described lane_offset_m to either side and those versions queried for places seen
  // the other way round (lane_query.hpp). 0: off.
  double lane_offset_m = 0.0;
  LaneQueryOptions lanes;
  // Consistent settings for a method and mode (the paper: 45 m).
  static RecognizerConfig make(Method method, Mode mode = Mode::Default, double range_m = 45.0);
};

// The database config of the places a recognizer adds: config.database with the mode and the
// descriptor frame it describes in (what a saved map records).
DatabaseConfig map_config(const RecognizerConfig& config);

// One place described (and added to the map) and what the map answered before it joined.
struct KeyframeResult {
  int keyframe = -1;               // the keyframe described (two-sided scans: an earlier one)
  std::vector<Candidate> matches;  // best first; empty when none passed the query options
};

class Recognizer {
 public:
  explicit Recognizer(const RecognizerConfig& config);
  // Continues an existing map (another session's, e.g. loaded from disk). Throws
  // std::invalid_argument when its places were described otherwise (method, mode, frame).
  Recognizer(const RecognizerConfig& config, Database map);

  // points: those the VO exported with this keyframe (world frame); reset: the VO restarted.
  // Returns the places described now, oldest first. Forward-only scans: this keyframe, or none
  // (the first init_frames after a reset). Two-sided scans (imitation.lookahead_m > 0): the
  // keyframes the VO is now lookahead_m past (usually one; all waiting ones at a reset).
  std::vector<KeyframeResult> add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                                           std::size_t n_points, bool reset = false);
  // End of the drive: describes the keyframes still waiting for their two-sided scan.
  std::vector<KeyframeResult> finish();

  const Database& database() const { return db_; }
  Database& database() { return db_; }
  const RecognizerConfig& config() const { return config_; }

 private:
  KeyframeResult recognise(const ReadyScan& ready);

  RecognizerConfig config_;
  ScanImitator imitator_;
  std::vector<ReadyScan> ready_;
  Database db_;
};

}  // namespace loopscan
