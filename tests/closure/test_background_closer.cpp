// Loop closing on a worker thread: the same results as the synchronous closer when the caller
// waits for a slot, a caller that never waits when the worker is slow, and a snapshot of the
// corrected poses that is consistent whenever it is read.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <type_traits>

#include "closure/drives.hpp"
#include "loopscan/closure/background_closer.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/sim/conditions.hpp"
#include "loopscan/sim/vo_simulator.hpp"

namespace loopscan {
namespace {

using closure::BackgroundConfig;
using closure::BackgroundLoopCloser;
using closure::KeyframeClosure;
using closure::LoopCloser;
using closure::LoopCloserConfig;

using test::Drive;
using test::same_clouds;
using test::same_loops;
using test::same_poses;

// The short built-in route (a block and its first street again) with a 2 % drifting VO.
const Drive& drive() {
  static const Drive d = test::drive(sim::Season::Summer, 1);
  return d;
}

template <typename Closer>
void stream(Closer& closer, const Drive& d) {
  for_each_keyframe(d.vo.poses, d.vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      closer.add_keyframe(k, p, n);
                    });
  closer.finish();
}

int accepted(const std::vector<closure::Loop>& loops) {
  int n = 0;
  for (const closure::Loop& l : loops) n += l.accepted();
  return n;
}

// A queue the caller waits on gives the synchronous closer's results exactly, even when the
// worker is much slower than the caller: a query sees the same places whatever the worker's
// pace (the band of recent places it skips is longer than the queue).
TEST(BackgroundLoopCloser, WaitingForASlotGivesTheSynchronousResults) {
  const Drive& d = drive();
  const LoopCloserConfig config = LoopCloserConfig::make(Method::ScanContext);
  LoopCloser sync(config);
  stream(sync, d);
  ASSERT_GE(accepted(sync.loops()), 3);
  for (const int capacity : {1, 4}) {
    BackgroundConfig bc;
    bc.queue_capacity = capacity;
    bc.when_full = BackgroundConfig::WhenFull::Wait;
    // Its candidates aligned and its places classified on several threads.
    LoopCloserConfig threaded_config = config;
    threaded_config.threads = capacity + 1;
    BackgroundLoopCloser background(threaded_config, bc);
    std::vector<int> closed_in_order;
    background.set_on_closed([&](const KeyframeClosure& c) {
      closed_in_order.push_back(c.keyframe);
      std::this_thread::sleep_for(std::chrono::microseconds(500));  // a slow worker
    });
    stream(background, d);
    EXPECT_TRUE(same_loops(sync.loops(), background.loops())) << "capacity " << capacity;
    EXPECT_TRUE(same_poses(sync.corrected_poses(), background.corrected_poses()));
    EXPECT_EQ(background.corrected_map().size(), sync.database().size());
    EXPECT_TRUE(same_clouds(background.place_clouds(), sync.place_clouds()));
    ASSERT_EQ(closed_in_order.size(), d.vo.poses.size());  // every keyframe, in input order
    for (std::size_t i = 0; i < d.vo.poses.size(); ++i)
      EXPECT_EQ(closed_in_order[i], d.vo.poses[i].id);
    EXPECT_GT(background.queue().waits, 0);  // the slow worker made the caller wait
    EXPECT_TRUE(background.poll().empty());  // closures went to the callback
  }
}

// The same across a VO reset, whose 30 scanless keyframes (the scan building up again) and the
// queue together would outnumber a band of 20 recent keyframes: waiting, every keyframe takes a
// slot, so the keyframes not yet integrated stay within the band and a query sees the same
// places.
TEST(BackgroundLoopCloser, WaitingGivesTheSynchronousResultsAcrossAVoReset) {
  const Drive d = test::with_vo_reset(drive(), 90);
  const int reset_id = d.vo.poses[90].id;
  LoopCloserConfig config = LoopCloserConfig::make(Method::ScanContext);
  config.recognition.query.exclude_recent = 20;
  int most_waiting = 0;  // keyframes queued or being integrated, after each add_keyframe
  const auto run = [&](auto& closer) {
    for_each_keyframe(
        d.vo.poses, d.vo.points, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
          closer.add_keyframe(k, p, n, k.id == reset_id);
          if constexpr (std::is_same_v<std::decay_t<decltype(closer)>, BackgroundLoopCloser>) {
            most_waiting = std::max(most_waiting, closer.queue().waiting);
          }
        });
    closer.finish();
  };
  LoopCloser sync(config);
  run(sync);
  ASSERT_GE(accepted(sync.loops()), 3);
  BackgroundConfig bc;
  bc.queue_capacity = 4;
  bc.when_full = BackgroundConfig::WhenFull::Wait;
  BackgroundLoopCloser background(config, bc);
  background.set_on_closed([&](const KeyframeClosure&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a worker far behind
  });
  run(background);
  // The worker sleeps through the reset's scanless keyframes: they wait for slots too.
  EXPECT_LE(most_waiting, bc.queue_capacity + 1);
  EXPECT_GT(background.queue().waits, 30);
  EXPECT_TRUE(same_loops(sync.loops(), background.loops()));
  EXPECT_TRUE(same_poses(sync.corrected_poses(), background.corrected_poses()));
}

// With a worker far slower than the keyframes and a queue of 2, the caller never waits: the
// oldest waiting keyframes are left unverified, yet every keyframe joins the graph, the queue
// never holds more than 2 places, and the loops the worker could verify still close.
TEST(BackgroundLoopCloser, ASlowWorkerSkipsVerificationButNeverStallsTheCaller) {
  const Drive& d = drive();
  const LoopCloserConfig config = LoopCloserConfig::make(Method::ScanContext);
  BackgroundConfig bc;
  bc.queue_capacity = 2;
  bc.when_full = BackgroundConfig::WhenFull::SkipVerification;
  BackgroundLoopCloser closer(config, bc);
  std::atomic<bool> slow{false};
  std::atomic<int> skipped_closures{0};
  std::atomic<std::size_t> given{0};
  closer.set_on_closed([&](const KeyframeClosure& c) {
    skipped_closures += c.skipped;
    // While slow, the worker lets the caller give 3 more keyframes before it takes the next:
    // far behind however fast its own work is (the caller never waits for it).
    const std::size_t at = given;
    while (slow && given < at + 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  int most_held = 0;
  const std::size_t n_keyframes = d.vo.poses.size();
  for_each_keyframe(d.vo.poses, d.vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      // The first street (the one the drive revisits at its end) at a pace the
                      // worker keeps up with, the next quarter of the drive far faster.
                      slow = given >= n_keyframes / 4 && given < n_keyframes / 2;
                      if (!slow) closer.wait();
                      closer.add_keyframe(k, p, n);
                      ++given;
                      most_held = std::max(most_held, closer.queue().holding_places);
                      EXPECT_EQ(closer.corrected_poses().size(), given.load());
                    });
  closer.finish();
  const closure::QueueStats q = closer.queue();
  EXPECT_EQ(q.waits, 0);
  EXPECT_GT(q.skipped, 10);
  EXPECT_LE(most_held, 2);
  const closure::StageTimes t = closer.times();
  EXPECT_EQ(t.keyframes, int(d.vo.poses.size()));
  EXPECT_EQ(t.skipped, q.skipped);
  EXPECT_EQ(closer.corrected_poses().size(), d.vo.poses.size());
  EXPECT_EQ(closer.corrected_map().size(), std::size_t(t.described - t.linked));
  EXPECT_GE(accepted(closer.loops()), 1);  // the revisit of the first street
  EXPECT_EQ(skipped_closures, q.skipped);
}

// Read from another thread while the worker solves: the snapshot always holds every keyframe
// given so far (none half-written: ids in input order, rigid poses), and at the end the graph's.
TEST(BackgroundLoopCloser, CorrectedPosesAreAConsistentSnapshotAtAnyTime) {
  const Drive& d = drive();
  BackgroundConfig bc;
  bc.when_full = BackgroundConfig::WhenFull::Wait;
  BackgroundLoopCloser closer(LoopCloserConfig::make(Method::ScanContext), bc);
  std::atomic<std::size_t> given{0};
  std::atomic<bool> done{false};
  std::atomic<int> reads{0}, bad{0};
  std::thread reader([&] {
    while (!done) {
      const std::size_t at_least = given;
      const std::vector<KeyframePose> poses = closer.corrected_poses();
      bool ok = poses.size() >= at_least && poses.size() <= d.vo.poses.size();
      for (std::size_t i = 0; ok && i < poses.size(); ++i) {
        const Eigen::Matrix3d R = poses[i].T_cam_world.leftCols<3>();
        ok = poses[i].id == d.vo.poses[i].id && poses[i].T_cam_world.allFinite() &&
             (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9;
      }
      bad += !ok;
      ++reads;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  for_each_keyframe(d.vo.poses, d.vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      closer.add_keyframe(k, p, n);
                      ++given;
                    });
  closer.finish();
  done = true;
  reader.join();
  EXPECT_GT(reads, 10);
  EXPECT_EQ(bad, 0);
  LoopCloser sync(LoopCloserConfig::make(Method::ScanContext));
  stream(sync, d);
  EXPECT_TRUE(same_poses(sync.corrected_poses(), closer.corrected_poses()));
}

// Waiting keyframes are placed where the graph will put them: by their VO motion from the
// latest estimate (checked against the synchronous closer before any loop moves the graph).
TEST(BackgroundLoopCloser, WaitingKeyframesContinueTheEstimateByTheirOdometry) {
  const Drive& d = drive();
  BackgroundConfig bc;
  bc.queue_capacity = 1000;
  BackgroundLoopCloser closer(LoopCloserConfig::make(Method::ScanContext), bc);
  std::atomic<bool> release{false};
  closer.set_on_closed([&](const KeyframeClosure&) {
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  LoopCloser sync(LoopCloserConfig::make(Method::ScanContext));
  const std::size_t n_keyframes = 40;  // before the revisit: no loop, no solve
  std::size_t i = 0;
  for_each_keyframe(d.vo.poses, d.vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      if (i++ >= n_keyframes) return;
                      closer.add_keyframe(k, p, n, i == 20);  // a VO reset half way
                      sync.add_keyframe(k, p, n, i == 20);
                    });
  EXPECT_GE(closer.queue().waiting, int(n_keyframes) - 1);  // the worker holds the first
  const std::vector<KeyframePose> a = sync.corrected_poses(), b = closer.corrected_poses();
  ASSERT_EQ(b.size(), n_keyframes);
  for (std::size_t k = 0; k < n_keyframes; ++k) {
    EXPECT_EQ(a[k].id, b[k].id);
    EXPECT_LT((a[k].T_cam_world - b[k].T_cam_world).norm(), 1e-9) << k;
  }
  release = true;
}

TEST(BackgroundLoopCloser, BadInputIsRefusedOnTheCallersThread) {
  BackgroundLoopCloser closer(LoopCloserConfig::make(Method::ScanContext));
  KeyframePose k;
  k.id = 4;
  closer.add_keyframe(k, nullptr, 0);
  EXPECT_THROW(closer.add_keyframe(k, nullptr, 0), std::invalid_argument);  // the same id again
  k.id = 5;
  k.T_cam_world(0, 3) = std::nan("");
  EXPECT_THROW(closer.add_keyframe(k, nullptr, 0), std::invalid_argument);
  closer.finish();
  EXPECT_EQ(closer.corrected_poses().size(), 1u);
  BackgroundConfig bad;
  bad.queue_capacity = 0;
  EXPECT_THROW(BackgroundLoopCloser(LoopCloserConfig::make(Method::ScanContext), bad),
               std::invalid_argument);
}

// Destroyed with keyframes still waiting and the worker busy: it stops without hanging.
TEST(BackgroundLoopCloser, StopsWithKeyframesStillWaiting) {
  const Drive& d = drive();
  BackgroundConfig bc;
  bc.queue_capacity = 1000;
  auto closer =
      std::make_unique<BackgroundLoopCloser>(LoopCloserConfig::make(Method::ScanContext), bc);
  closer->set_on_closed(
      [](const KeyframeClosure&) { std::this_thread::sleep_for(std::chrono::milliseconds(2)); });
  for_each_keyframe(d.vo.poses, d.vo.points,
                    [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                      closer->add_keyframe(k, p, n);
                    });
  EXPECT_GT(closer->queue().waiting, 0);
  closer.reset();
}

}  // namespace
}  // namespace loopscan
