#pragma once
// `describe --lidar`: real LiDAR scans (KITTI .bin[.gz], PCD, PLY) described like imitated
// scans, one place per scan, written like any described sequence.
#include <string>
#include <vector>

namespace loopscan::cli {

struct LidarDescribeArgs {
  std::string method, mode, out, params = "paper";  // paper | scan-context (80 m, max height)
  std::vector<std::string> scans;                   // files or folders
  double range_m = 0;                               // 0: the params' range
  int threads = 1;
};

void run_lidar_describe(const LidarDescribeArgs& a);

}  // namespace loopscan::cli
