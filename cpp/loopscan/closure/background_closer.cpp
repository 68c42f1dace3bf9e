#include "loopscan/closure/background_closer.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

namespace loopscan::closure {
namespace {

bool holds_place(const PreparedKeyframe& p) { return p.has_scan && !p.out.skipped; }

}  // namespace

void validate(const BackgroundConfig& c) {
  if (c.queue_capacity < 1 || c.queue_capacity > 100000 || c.max_unpolled < 0) {
    throw std::invalid_argument(
        "background closer: queue_capacity in [1, 100000], max_unpolled >= 0");
  }
}

BackgroundLoopCloser::BackgroundLoopCloser(const LoopCloserConfig& config,
                                           const BackgroundConfig& background)
    : BackgroundLoopCloser(config, Database(map_config(config.recognition)), {}, background) {}

BackgroundLoopCloser::BackgroundLoopCloser(const LoopCloserConfig& config, Database map,
                                           std::vector<PlaceCloud> map_clouds,
                                           const BackgroundConfig& background)
    : background_(background), closer_(config, std::move(map), std::move(map_clouds)) {
  validate(background_);
  worker_ = std::thread([this] { work(); });
}

BackgroundLoopCloser::~BackgroundLoopCloser() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  slot_free_.notify_all();
  idle_.notify_all();
  worker_.join();
}

void BackgroundLoopCloser::set_on_closed(std::function<void(const KeyframeClosure&)> callback) {
  const std::lock_guard lock(mutex_);
  on_closed_ = std::move(callback);
}

void BackgroundLoopCloser::rethrow_worker_error() {
  if (error_) std::rethrow_exception(error_);
}

KeyframeClosure BackgroundLoopCloser::add_keyframe(const KeyframePose& keyframe,
                                                   const IdPoint* points, std::size_t n_points,
                                                   bool reset) {
  return enqueue(closer_.prepare(keyframe, points, n_points, reset));
}

KeyframeClosure BackgroundLoopCloser::add_scan(const KeyframePose& keyframe, const Cloud& in_range,
                                               bool reset) {
  return enqueue(closer_.prepare_scan(keyframe, in_range, reset));
}

KeyframeClosure BackgroundLoopCloser::enqueue(PreparedKeyframe prepared) {
  KeyframeClosure known = prepared.out;
  {
    std::unique_lock lock(mutex_);
    rethrow_worker_error();
    stats_.last_wait_ms = 0;
    // Waiting, every keyframe takes a slot: the query's band of recent places counts every
    // keyframe given, so a run of scanless ones (after a VO reset) must not lengthen the span
    // of keyframes not yet integrated past it.
    const bool wait = background_.when_full == BackgroundConfig::WhenFull::Wait;
    const auto taken = [&] { return wait ? int(queue_.size()) : full_entries_; };
    if ((wait || holds_place(prepared)) && taken() >= background_.queue_capacity) {
      if (wait) {
        const auto start = std::chrono::steady_clock::now();
        slot_free_.wait(lock,
                        [&] { return error_ || stop_ || taken() < background_.queue_capacity; });
        rethrow_worker_error();
        stats_.last_wait_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        stats_.waited_ms += stats_.last_wait_ms;
        ++stats_.waits;
      } else {
        for (PreparedKeyframe& waiting : queue_) {
          if (!holds_place(waiting)) continue;
          waiting.skip();
          --full_entries_;
          ++stats_.skipped;
          break;
        }
      }
    }
    if (holds_place(prepared)) ++full_entries_;
    queue_.push_back(std::move(prepared));
  }
  work_ready_.notify_one();
  return known;
}

void BackgroundLoopCloser::work() {
  for (;;) {
    PreparedKeyframe prepared;
    {
      std::unique_lock lock(mutex_);
      work_ready_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      prepared = std::move(queue_.front());
      queue_.pop_front();
      if (holds_place(prepared)) --full_entries_;
      in_flight_.emplace(prepared.keyframe, prepared.reset);
    }
    slot_free_.notify_all();
    const KeyframePose input = prepared.keyframe;
    try {
      const std::lock_guard closer_lock(closer_mutex_);
      publish(closer_.integrate(std::move(prepared)), input);
    } catch (...) {
      {
        const std::lock_guard lock(mutex_);
        error_ = std::current_exception();
        in_flight_.reset();
      }
      slot_free_.notify_all();
      idle_.notify_all();
      return;
    }
    idle_.notify_all();
  }
}

void BackgroundLoopCloser::publish(KeyframeClosure out, const KeyframePose& input) {
  // The poses the snapshot lacks, read while no other thread changes the closer.
  const bool moved = closer_.pose_revision() != snapshot_revision_;
  std::vector<KeyframePose> poses = closer_.corrected_poses(moved ? 0 : snapshot_.size());
  std::function<void(const KeyframeClosure&)> callback;
  {
    const std::lock_guard lock(mutex_);
    if (moved) {
      snapshot_ = std::move(poses);
      snapshot_revision_ = closer_.pose_revision();
    } else {
      snapshot_.insert(snapshot_.end(), poses.begin(), poses.end());
    }
    last_input_ = input;
    in_flight_.reset();
    callback = on_closed_;
    if (!callback && background_.max_unpolled > 0) {
      if (int(closures_.size()) >= background_.max_unpolled) {
        closures_.pop_front();
        ++stats_.dropped_closures;
      }
      closures_.push_back(std::move(out));
    }
  }
  if (callback) callback(out);
}

std::vector<KeyframeClosure> BackgroundLoopCloser::poll() {
  const std::lock_guard lock(mutex_);
  rethrow_worker_error();
  std::vector<KeyframeClosure> out(std::make_move_iterator(closures_.begin()),
                                   std::make_move_iterator(closures_.end()));
  closures_.clear();
  return out;
}

std::vector<KeyframePose> BackgroundLoopCloser::corrected_poses() const {
  const std::lock_guard lock(mutex_);
  std::vector<KeyframePose> out = snapshot_;
  KeyframePose previous_input = last_input_;
  // As LoopCloser::add_graph_node places a node: after the previous one's estimate by the VO's
  // motion between them, or where the VO put it when a run starts.
  const auto continue_with = [&](const KeyframePose& input, bool reset) {
    KeyframePose k = input;
    if (!out.empty() && !reset) {
      const Eigen::Isometry3d T_previous_this =
          isometry(previous_input.T_cam_world) * isometry(input.T_cam_world).inverse();
      k.T_cam_world =
          (T_previous_this.inverse() * isometry(out.back().T_cam_world)).matrix().topRows<3>();
    }
    out.push_back(k);
    previous_input = input;
  };
  if (in_flight_) continue_with(in_flight_->first, in_flight_->second);
  for (const PreparedKeyframe& waiting : queue_) continue_with(waiting.keyframe, waiting.reset);
  return out;
}

void BackgroundLoopCloser::wait() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [&] { return error_ || (queue_.empty() && !in_flight_); });
  rethrow_worker_error();
}

GraphSolve BackgroundLoopCloser::finish() {
  wait();
  const std::lock_guard closer_lock(closer_mutex_);
  const GraphSolve solve = closer_.finish();
  std::vector<KeyframePose> poses = closer_.corrected_poses();
  const std::lock_guard lock(mutex_);
  snapshot_ = std::move(poses);
  snapshot_revision_ = closer_.pose_revision();
  return solve;
}

QueueStats BackgroundLoopCloser::queue() const {
  const std::lock_guard lock(mutex_);
  QueueStats s = stats_;
  s.waiting = int(queue_.size()) + (in_flight_ ? 1 : 0);
  s.holding_places = full_entries_;
  return s;
}

std::vector<Loop> BackgroundLoopCloser::loops() const {
  return read([](const LoopCloser& c) { return c.loops(); });
}
StageTimes BackgroundLoopCloser::times() const {
  return read([](const LoopCloser& c) { return c.times(); });
}
Database BackgroundLoopCloser::corrected_map() const {
  return read([](const LoopCloser& c) { return c.corrected_map(); });
}
std::vector<PlaceCloud> BackgroundLoopCloser::place_clouds() const {
  return read([](const LoopCloser& c) { return c.place_clouds(); });
}
bool BackgroundLoopCloser::anchored() const {
  return read([](const LoopCloser& c) { return c.anchored(); });
}
int BackgroundLoopCloser::anchored_at() const {
  return read([](const LoopCloser& c) { return c.anchored_at(); });
}

}  // namespace loopscan::closure
