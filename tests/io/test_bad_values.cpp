// Values that parse but must not be accepted: NaN, infinities, magnitudes beyond the bounds
// of io::limits, lines without end, database records with a valid checksum but impossible
// contents. Each is an InputError naming the file and the line or byte.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <limits>

#include "loopscan/core/database/database.hpp"
#include "loopscan/io/bow_file.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/parse_numbers.hpp"
#include "loopscan/io/sodso.hpp"
#include "loopscan/io/vocabulary_file.hpp"
#include "support/io_fixture.hpp"

namespace loopscan {
namespace {

using test::error_of;
using test::has;
using BadValues = test::IoFixture;
using namespace io;
namespace fs = std::filesystem;

TEST_F(BadValues, TextLinesAreBoundedEvenWithoutALineBreak) {
  const std::string endless(std::size_t{5} << 20, '7');  // 5 MiB, no '\n' (like /dev/zero)
  for (const std::string& p : {file("long.txt", endless), gz_file("long.txt.gz", endless)}) {
    const std::string msg = error_of([&] { read_matrix_text(p); });
    EXPECT_TRUE(has(msg, p + ":1: expected lines of at most 4 MiB")) << msg;
  }
  // A line just under the bound is read.
  std::string wide;
  for (int i = 0; i < 200000; ++i) wide += "1.5 ";
  EXPECT_EQ(read_matrix_text(file("wide.txt", wide + "\n")).cols(), 200000);
}

// A small gzip file can expand to billions of valid records: readers count them. (The bound
// itself, 10^8, is too many records to write here; its check is exercised directly.)
TEST_F(BadValues, RecordCountsAreBounded) {
  LineReader reader(file("r.txt", "1\n"));
  std::string_view line;
  reader.next(line);
  EXPECT_NO_THROW(check_record_count(reader, limits::kMaxRecords, "points"));
  const std::string msg =
      error_of([&] { check_record_count(reader, limits::kMaxRecords + 1, "points"); });
  EXPECT_TRUE(has(msg, "r.txt:1: expected at most 100000000 points in one file")) << msg;
}

TEST_F(BadValues, MatrixValuesMustBeFiniteAndWithinTheBound) {
  const auto read = [](auto p) { read_matrix_text(p); };
  expect_bad(read, "1 2\n3 nan\n", 2, "finite and within +-1e+30");
  expect_bad(read, "1 inf\n", 1, "finite");
  expect_bad(read, "1 -1e31\n", 1, "+-1e+30");
  expect_bad(read, "1 1e400\n", 1, "finite");  // overflows double: infinity
  EXPECT_EQ(read_matrix_text(file("ok.txt", "1e29 -1e29\n"))(0, 1), -1e29);
  expect_bad([](auto p) { read_matrix_text(p, 2, 1.0); }, "0.5 1.5\n", 1, "+-1");
}

TEST_F(BadValues, PosesAndGroundTruthMustBeFiniteAndWithinABillionMetres) {
  const auto poses = [](auto p) { read_sodso_poses(p); };
  expect_bad(poses, "0 1 0 0 nan 0 1 0 0 0 0 1 0\n", 1, "finite");
  expect_bad(poses, "0 1 0 0 1e10 0 1 0 0 0 0 1 0\n", 1, "+-1e+09");
  const auto kitti = [](auto p) { read_kitti_poses(p); };
  expect_bad(kitti, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 inf 0 1 0 0 0 0 1 0\n", 2, "finite");
  const auto gps = [](auto p) { read_positions(p, GtFormat::RobotCar); };
  expect_bad(gps, "5735000 620000 -1\n1e308 620000 -1\n", 2, "+-1e+09");
  // RobotCar's real magnitudes (northings ~5.7e6 m) are well inside.
  EXPECT_EQ(read_positions(file("g.txt", "5735000.5 620000 -1\n"), GtFormat::RobotCar).size(), 1u);
}

TEST_F(BadValues, PointsBeyondTheBoundAreSkippedAndCountedLikeNaN) {
  PointReadStats stats;
  const auto pts = read_sodso_points(
      file("p.txt", "0 1 2 3 10\n0 1e10 2 3 10\n0 1 nan 3 10\n0 1 2 3 inf\n1 -4 5 6 20\n"), &stats);
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(stats.non_finite_skipped, 3u);
  EXPECT_EQ(pts[1].p_world.x(), -4.0);
}

TEST_F(BadValues, CalibrationAndTimesMustBeFinite) {
  const std::string p1 = "P1: 700 0 600 -380 0 700 180 0 0 0 1 0\n";
  expect_bad([](auto p) { read_kitti_calib(p); }, "P0: 700 0 600 0 0 nan 180 0 0 0 1 0\n" + p1, 1,
             "finite");
  const fs::path seq = dir_ / "seq";
  fs::create_directories(seq);
  std::ofstream(seq / "calib.txt") << "P0: 700 0 600 0 0 700 180 0 0 0 1 0\n" << p1;
  std::ofstream(seq / "times.txt") << "0\ninf\n";
  const std::string msg = error_of([&] { open_kitti_sequence(seq.string()); });
  EXPECT_TRUE(has(msg, "times.txt:2: expected one timestamp")) << msg;
  std::ofstream(seq / "times.txt") << "1403636579763555584\n1403636579813555456\n";  // EuRoC ns
  EXPECT_TRUE(has(error_of([&] { open_kitti_sequence(seq.string()); }), "image_0/000000.png"));
  // Calibrations a rectified pair cannot have: a P1 focal length unlike P0's (which made a
  // 5e8 m baseline), baselines beyond 100 m, focal lengths beyond 1e5 px.
  const std::string p0 = "P0: 700 0 600 0 0 700 180 0 0 0 1 0\n";
  const auto calib = [](auto p) { read_kitti_calib(p); };
  expect_bad(calib, p0 + "P1: 7e-07 0 600 -386 0 700 180 0 0 0 1 0\n", 0,
             "the focal length of P0 in P1");
  expect_bad(calib, p0 + "P1: 700 0 600 -7e5 0 700 180 0 0 0 1 0\n", 0, "baseline in (0, 100] m");
  expect_bad(calib, "P0: 7e6 0 600 0 0 7e6 180 0 0 0 1 0\nP1: 7e6 0 600 -1 0 7e6 180 0 0 0 1 0\n",
             0, "focal lengths in [1, 1e5] px");
  EXPECT_NEAR(read_kitti_calib(file("ok.txt", p0 + p1)).baseline_m, 380.0 / 700.0, 1e-12);
}

TEST_F(BadValues, BowVectorsAndVocabulariesMustHoldFiniteWeightsAndBoundedWords) {
  const auto bow = [](auto p) { read_bow_vectors(p); };
  expect_bad(bow, "0 0.5 3 nan\n", 1, "weights finite and > 0");
  expect_bad(bow, "0 0.5 3 1e39\n", 1, "weights finite");  // beyond single precision
  expect_bad(bow, "0 0.5 16777216 0.5\n", 1, "at most 16777215");
  EXPECT_EQ(read_bow_vectors(file("ok.txt", "0 0.5 16777215 0.5\n"))[0].size(), 2u);
  const std::string node =
      " 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 ";
  expect_bad([](auto p) { read_orbvoc_text(p); }, "2 1 0 0\n0 1" + node + "nan\n", 2, "finite");
  // Binary: a NaN weight behind a valid checksum.
  VocabularyData v;
  v.branching = 2;
  v.depth = 1;
  v.nodes = {{0, true, {}, 0.5f}, {0, true, {}, std::nanf("")}};
  save_vocabulary((dir_ / "v.bin").string(), v);
  const std::string msg = error_of([&] { load_vocabulary((dir_ / "v.bin").string()); });
  EXPECT_TRUE(has(msg, "node 2: expected a finite non-negative weight")) << msg;
}

// A saved database with bytes patched at `offset` and the checksum recomputed, so that only
// the value checks can catch it.
class PatchedDatabase : public BadValues {
 protected:
  std::string saved() {
    DatabaseConfig cfg;
    cfg.method = Method::Delight;
    Database db(cfg);
    Signature s = Signature::Zero(rows_per_place(cfg.method), signature_columns(cfg.method));
    s(0, 3) = 2;
    db.add({0, 7}, {s}, Pose3x4::Identity());
    save_database(db, (dir_ / "ok.db").string());
    return slurp((dir_ / "ok.db").string());
  }
  template <typename T>
  std::string patched(std::size_t offset, T value) {
    std::string bytes = saved();
    std::memcpy(&bytes[offset], &value, sizeof value);
    const auto crc = static_cast<std::uint32_t>(crc32(
        0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size() - 4)));
    std::memcpy(&bytes[bytes.size() - 4], &crc, 4);
    return file("patched.db", bytes);
  }
  std::string load_error(const std::string& path) {
    return error_of([&] { load_database(path); });
  }
  // Header 99 bytes (version 6; the bird's-eye weight window at 71 and 79); a place: session,
  // keyframe, pose flag, frame (9 f32), pose (12 f64), payload.
  static constexpr std::size_t kMode = 44, kFrameKind = 45, kWindow = 71, kPlace = 99,
                               kFrame = kPlace + 9, kPose = kFrame + 36, kPayload = kPose + 96;
};

TEST_F(PatchedDatabase, ValidChecksumButImpossibleValuesAreRejected) {
  EXPECT_EQ(load_database(patched(kPayload, 2.0f)).size(), 1u);  // the patch itself is sound
  EXPECT_TRUE(has(load_error(patched(20, -1e308)), "structure weight"))
      << load_error(patched(20, -1e308));
  EXPECT_TRUE(has(load_error(patched(20, std::nan(""))), "structure weight"));
  const std::string nan_payload = load_error(patched(kPayload + 8, std::nanf("")));
  EXPECT_TRUE(has(nan_payload, "place 0") && has(nan_payload, "NaN")) << nan_payload;
  EXPECT_TRUE(
      has(load_error(patched(kPayload, std::numeric_limits<float>::infinity())), "place 0"));
  EXPECT_TRUE(has(load_error(patched(kFrame, 2.0f)), "not a rotation"));
  EXPECT_TRUE(
      has(load_error(patched(kPose + 24, std::numeric_limits<double>::infinity())), "pose"));
  EXPECT_TRUE(has(load_error(patched(kPlace, std::int32_t{-5})), ">= 0"));
  EXPECT_TRUE(has(load_error(patched(kMode, std::uint8_t{2})), "mode 2"))
      << load_error(patched(kMode, std::uint8_t{2}));
  EXPECT_TRUE(has(load_error(patched(kFrameKind, std::uint8_t{4})), "frame kind 4"));
  EXPECT_TRUE(has(load_error(patched(kFrameKind + 1, std::uint8_t{2})), "cell kind 2"));
  const std::string window = load_error(patched(kWindow, std::nan("")));
  EXPECT_TRUE(has(window, "taper_end_m must exceed taper_start_m")) << window;
  EXPECT_FALSE(load_database(patched(kMode, std::uint8_t{255})).config().mode.has_value());
}

TEST_F(PatchedDatabase, BinaryErrorsNameTheByteAndTheProblem) {
  std::string bytes = saved();
  bytes[kPayload + 1] = static_cast<char>(bytes[kPayload + 1] ^ 0x10);  // a flip, CRC unchanged
  const std::string p = file("flipped.db", bytes);
  const std::string msg = load_error(p);
  EXPECT_EQ(msg.rfind(p + ": byte ", 0), 0u) << msg;
  EXPECT_TRUE(has(msg, ": checksum mismatch")) << msg;
  EXPECT_FALSE(has(msg, "expected byte")) << msg;
}

}  // namespace
}  // namespace loopscan
