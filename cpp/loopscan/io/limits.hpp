#pragma once
// Upper bounds on what an input file may imply, so that a malformed or hostile file ends in a
// clear InputError instead of unbounded memory or time. Each bound is far above any real
// dataset (KITTI, RobotCar, EuRoC, the authors' exports) and is named in the error.
#include <cstddef>
#include <cstdint>

namespace loopscan::io::limits {

// Text: one line (a 2400-number Scan Context row is ~40 KB).
constexpr std::size_t kMaxLineBytes = std::size_t{4} << 20;
// Coordinates of poses, ground truth and points, metres (RobotCar northings are ~6e6).
constexpr double kMaxCoordinateM = 1e9;
// Signature values and other float payloads: representable in single precision with room.
constexpr double kMaxSignatureValue = 1e30;
// Images: each side and the pixel count (64 Mpx), and the encoded file.
constexpr int kMaxImageSide = 32768;
constexpr std::int64_t kMaxImagePixels = std::int64_t{1} << 26;
constexpr std::size_t kMaxImageFileBytes = std::size_t{256} << 20;

// Records in one text file (points, poses, ids, pairs, BoW places, vocabulary nodes): a few
// gigabytes once parsed, ~20x a KITTI-length SO-DSO export (4.5 million points). Numbers in
// one matrix file (signatures): 2^28 doubles, 2 GB.
constexpr std::size_t kMaxRecords = 100'000'000;
constexpr std::size_t kMaxMatrixValues = std::size_t{1} << 28;

// Bag-of-words: word ids (ORBvoc.txt has 10^6 words; k 10, L 7 would have 10^7).
constexpr int kMaxWordId = (1 << 24) - 1;

}  // namespace loopscan::io::limits
