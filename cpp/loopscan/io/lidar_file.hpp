#pragma once
// LiDAR scans from files: KITTI velodyne `.bin` (float32 x y z reflectance, little endian),
// gzip-compressed or not, PCD (ascii or binary) and PLY (ascii or binary_little_endian). The
// points stay in the sensor's frame (z up); the intensity is the file's reflectance/intensity
// field as stored (0 when it has none).
#include <string>
#include <vector>

#include "loopscan/core/types.hpp"

namespace loopscan::io {

struct LidarReadStats {
  std::size_t non_finite_skipped = 0;  // no-return points (NaN) some drivers write
  bool has_intensity = false;
};

// Throws InputError naming the file and the byte / header line on a malformed file: a `.bin`
// whose size is not a multiple of 16, a PCD/PLY header without x y z, an unsupported encoding
// (binary_compressed PCD, big-endian PLY), a body shorter than the header says.
Cloud read_lidar_scan(const std::string& path, LidarReadStats* stats = nullptr);

// The scan files named on a command line: files as given, folders expanded to their `.bin`,
// `.pcd` and `.ply` files (each also `.gz`) in name order. Throws InputError on a missing path or a
// folder without scans.
std::vector<std::string> lidar_scan_files(const std::vector<std::string>& paths);

}  // namespace loopscan::io
