// Real LiDAR scans as loop-closing places (LoopCloser::add_scan): the KITTI 08 reverse revisit
// (two Velodyne scans 3.64 m apart, driven in opposite directions) is verified, with a relative
// pose close to KITTI's ground truth. Skipped without ../shared.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/core/scan/lidar_scan.hpp"
#include "loopscan/io/lidar_file.hpp"
#include "support/test_support.hpp"

namespace loopscan::closure {
namespace {
namespace fs = std::filesystem;

// KITTI ground truth of one frame: camera-to-world.
Eigen::Isometry3d kitti_pose(const fs::path& file, int frame) {
  std::ifstream in(file);
  std::string line;
  for (int f = 0; std::getline(in, line); ++f) {
    if (f != frame) continue;
    std::istringstream row(line);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int k = 0; k < 12; ++k) row >> T.matrix()(k / 4, k % 4);
    return T;
  }
  ADD_FAILURE() << file << " has no frame " << frame;
  return Eigen::Isometry3d::Identity();
}

TEST(LoopCloserLidar, VerifiesTheKittiReverseRevisitAtTheTruePose) {
  const fs::path shared = test::shared_dir();
  const fs::path pair = shared / "data/real/kitti08-lidar-revisit";
  const fs::path poses = shared / "data/kitti/poses/08.txt";
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(pair / "000720.bin.gz") && fs::exists(poses),
                               pair << " and " << poses);
  LoopCloserConfig config = LoopCloserConfig::make(Method::ScanContext);
  // Two places only: no recent-place mask, and the z-score gate needs a populated map's rows.
  config.recognition.query.exclude_recent = 0;
  config.max_candidate_distance = std::numeric_limits<double>::infinity();
  LoopCloser closer(config);
  const int frames[2] = {720, 1500};
  KeyframeClosure last;
  for (int i = 0; i < 2; ++i) {
    const std::string name = (i == 0 ? "000720" : "001500");
    const Cloud scan = io::read_lidar_scan((pair / (name + ".bin.gz")).string());
    // The Velodyne's axes turned into the camera convention; KITTI's small velodyne-to-camera
    // offset (~0.3 m) is left out, so the scan sits near, not exactly at, the camera pose.
    KeyframePose pose;
    pose.id = frames[i];
    pose.T_cam_world = kitti_pose(poses, frames[i]).inverse().matrix().topRows<3>();
    last = closer.add_scan(pose, lidar_in_range(scan, config.recognition.imitation.range_m));
  }
  ASSERT_TRUE(last.described);
  ASSERT_FALSE(last.verified.empty()) << "no candidate verified";
  const Loop& loop = last.verified.front();
  EXPECT_EQ(loop.match.keyframe, 720);
  // One loop cannot be confirmed by another (consistency): it stays pending, not refused.
  EXPECT_EQ(loop.verdict, Verdict::Pending) << to_string(loop.verdict);
  const Eigen::Isometry3d truth =
      kitti_pose(poses, 1500).inverse() * kitti_pose(poses, 720);  // match camera -> query camera
  const Eigen::Isometry3d error = truth.inverse() * loop.T_query_match;
  const double degrees = Eigen::AngleAxisd(error.linear()).angle() * 180 / M_PI;
  std::printf(
      "KITTI 08 LiDAR loop: overlap %.2f, rmse %.2f m, error %.2f m (%.2f %.2f %.2f) / %.2f deg\n",
      loop.overlap, loop.rmse_m, error.translation().norm(), error.translation().x(),
      error.translation().y(), error.translation().z(), degrees);
  // Horizontally (camera x, z): conjugating by the omitted ~0.3 m offset moves a 150-degree
  // relative pose by up to ~0.6 m, and the ground truth has its own error; measured 1.0 m.
  // Vertically KITTI's poses put the two frames 1.1 m apart on the same street, where the two
  // scans' ground planes coincide after the alignment: that component is not checked.
  EXPECT_LT(std::hypot(error.translation().x(), error.translation().z()), 1.3);
  EXPECT_LT(degrees, 3.0);
}

}  // namespace
}  // namespace loopscan::closure
