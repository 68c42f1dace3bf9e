#pragma once
// Loop closing off the caller's thread: the caller (a VO thread) imitates, describes and
// queries each keyframe (LoopCloser::prepare, about a millisecond); a worker thread verifies the
// candidates, solves the pose graph and grows the map (LoopCloser::integrate). Results reach
// the caller through poll() or a callback; corrected_poses() is a consistent snapshot at any
// time. The synchronous LoopCloser stays for deterministic use.
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "loopscan/closure/loop_closer.hpp"

namespace loopscan::closure {

struct BackgroundConfig {
  // Keyframes prepared but not yet taken by the worker (SkipVerification: those holding a
  // place; Wait: all). At a keyframe a second the worker is behind only during a long graph
  // solve; replaying a recording is another matter (WhenFull).
  int queue_capacity = 32;
  enum class WhenFull {
    // The oldest waiting keyframe drops its place: it still joins the graph (its odometry edge),
    // but is neither verified nor added to the map. The caller never waits: for a live robot.
    SkipVerification,
    // The caller waits for a free slot: for replaying a recording faster than real time, where
    // every keyframe should be verified (the results then equal the synchronous closer's).
    Wait,
  };
  WhenFull when_full = WhenFull::SkipVerification;
  // Closures kept for poll(); beyond this the oldest are dropped (counted in QueueStats).
  int max_unpolled = 100000;
};

void validate(const BackgroundConfig& config);

struct QueueStats {
  int waiting = 0;            // keyframes queued or being integrated now
  int holding_places = 0;     // ... of the queued ones, those still holding their place
  long waits = 0;             // add_keyframe calls that waited for a slot (WhenFull::Wait)
  double waited_ms = 0;       // ... and their total wait
  double last_wait_ms = 0;    // the wait of the latest add_keyframe call
  long skipped = 0;           // keyframes left unverified (WhenFull::SkipVerification)
  long dropped_closures = 0;  // closures dropped unpolled (max_unpolled)
};

class BackgroundLoopCloser {
 public:
  explicit BackgroundLoopCloser(const LoopCloserConfig& config,
                                const BackgroundConfig& background = {});
  // Continues a saved map, as LoopCloser's constructor of the same arguments.
  BackgroundLoopCloser(const LoopCloserConfig& config, Database map,
                       std::vector<PlaceCloud> map_clouds, const BackgroundConfig& background = {});
  ~BackgroundLoopCloser();  // stops the worker; keyframes still queued are dropped
  BackgroundLoopCloser(const BackgroundLoopCloser&) = delete;
  BackgroundLoopCloser& operator=(const BackgroundLoopCloser&) = delete;

  // The caller's half of LoopCloser::add_keyframe / add_scan; returns what it knows now
  // (keyframe, described, candidates). The rest arrives by poll() or the callback. Rethrows an
  // error the worker met.
  KeyframeClosure add_keyframe(const KeyframePose& keyframe, const IdPoint* points,
                               std::size_t n_points, bool reset = false);
  KeyframeClosure add_scan(const KeyframePose& keyframe, const Cloud& in_range, bool reset = false);

  // Called on the worker's thread with each keyframe's closure, as it completes (instead of
  // keeping it for poll). Set it before the first keyframe; it must not call this closer.
  void set_on_closed(std::function<void(const KeyframeClosure&)> callback);
  // Closures completed since the last poll, in input order.
  std::vector<KeyframeClosure> poll();

  // Every keyframe given so far: the integrated ones at the graph's latest estimate, the
  // waiting ones continued from it by their VO odometry (as the graph will place them).
  // Never waits for the worker.
  std::vector<KeyframePose> corrected_poses() const;

  // Waits until the worker has integrated every queued keyframe.
  void wait();
  // wait(), then LoopCloser::finish.
  GraphSolve finish();

  QueueStats queue() const;
  // Copies of the closer's state; each waits for the keyframe being integrated, not the queue.
  std::vector<Loop> loops() const;
  StageTimes times() const;
  Database corrected_map() const;
  std::vector<PlaceCloud> place_clouds() const;
  bool anchored() const;
  int anchored_at() const;
  const LoopCloserConfig& config() const { return closer_.config(); }

 private:
  template <typename Read>
  auto read(Read&& what) const {  // a copy of the closer's state, between two keyframes
    const std::lock_guard lock(closer_mutex_);
    return what(closer_);
  }
  KeyframeClosure enqueue(PreparedKeyframe prepared);
  void work();
  void rethrow_worker_error();
  // The worker, holding closer_mutex_: brings the snapshot up to date with the closer.
  void publish(KeyframeClosure out, const KeyframePose& input);

  BackgroundConfig background_;
  LoopCloser closer_;
  mutable std::mutex closer_mutex_;  // held while the worker integrates (the closer's state)

  mutable std::mutex mutex_;  // the queue, the snapshot, the closures, the counters
  std::condition_variable work_ready_, slot_free_, idle_;
  std::deque<PreparedKeyframe> queue_;
  int full_entries_ = 0;  // queued keyframes that still hold their place
  std::optional<std::pair<KeyframePose, bool>> in_flight_;  // being integrated: pose, reset
  std::vector<KeyframePose> snapshot_;                      // integrated keyframes, corrected
  KeyframePose last_input_;                                 // VO pose of the last integrated
  long snapshot_revision_ = -1;
  std::deque<KeyframeClosure> closures_;
  QueueStats stats_;
  std::exception_ptr error_;
  bool stop_ = false;
  std::function<void(const KeyframeClosure&)> on_closed_;
  std::thread worker_;
};

}  // namespace loopscan::closure
