// Tests for loopscan::io: readers, writers, error reporting and the shared k06 fixture.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>
#include <limits>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include <loopscan/io/atomic_file.hpp>
#include <loopscan/io/errors.hpp>
#include <loopscan/io/ground_truth_files.hpp>
#include <loopscan/io/incoming_ids.hpp>
#include <loopscan/io/line_reader.hpp>
#include <loopscan/io/matrix_text.hpp>
#include <loopscan/io/parse_numbers.hpp>
#include <loopscan/io/sodso.hpp>

#include "support/io_fixture.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;
using Positions = std::vector<Eigen::Vector3d>;
using namespace loopscan::io;

namespace {

using loopscan::test::error_of;
using loopscan::test::expect_input_error;
using loopscan::test::has;
using IoTest = loopscan::test::IoFixture;

std::vector<std::string> read_all_lines(const std::string& path) {
  LineReader reader(path);
  std::vector<std::string> lines;
  std::string_view line;
  while (reader.next(line)) lines.emplace_back(line);
  EXPECT_EQ(reader.line_number(), lines.size());
  return lines;
}

}  // namespace

TEST(ParseNumberTest, AcceptsAndRejects) {
  const auto ok = [](std::string_view t, auto v) {  // parses into the type of `v`
    EXPECT_TRUE(parse_number(t, v)) << t;
    return v;
  };
  EXPECT_EQ(ok("+1.5e3", 0.0), 1500.0);
  EXPECT_TRUE(std::isinf(ok("1e400", 0.0)));
  EXPECT_TRUE(std::isnan(ok("nan", 0.0)));
  EXPECT_EQ(ok("-42", 0), -42);
  EXPECT_EQ(ok("68.2", 0.f), 68.2f);  // float parse, not double-then-cast
  double d = 0;
  int i = 0;
  for (const char* junk : {"", "+", "1.2.3", "abc", "1,5", "--1", "0x10"})
    EXPECT_FALSE(parse_number(junk, d)) << junk;
  EXPECT_FALSE(parse_number("7.0", i) || parse_number("99999999999", i));
}

TEST_F(IoTest, LineReaderPlainAndGzip) {
  const std::string p = file("a.txt", "one\r\ntwo\n\nlast");
  EXPECT_EQ(read_all_lines(p), (std::vector<std::string>{"one", "two", "", "last"}));
  EXPECT_TRUE(read_all_lines(file("empty.txt", "")).empty());
  // gzip input spanning many read buffers, with a line longer than the buffer.
  std::string content;
  for (int i = 0; i < 200000; ++i) content += std::to_string(i) + " x\n";
  const std::string long_line(3 << 20, 'z');  // longer than the 1 MiB read buffer
  content += long_line + "\nend\n";
  const auto lines = read_all_lines(gz_file("big.txt.gz", content));
  ASSERT_EQ(lines.size(), 200002u);
  EXPECT_EQ(lines[123456], "123456 x");
  EXPECT_EQ(lines[200000], long_line);
  EXPECT_EQ(lines[200001], "end");
}

TEST_F(IoTest, LineReaderErrors) {
  const std::string missing = (dir_ / "missing.txt").string();
  expect_input_error([&] { LineReader r(missing); }, missing, 0, "a readable file");
  expect_input_error([&] { LineReader r(dir_.string()); }, dir_.string(), 0, "a readable file");
  const std::string bytes = slurp(gz_file("t.gz", std::string(800000, '7')));
  const std::string cut = file("cut.gz", bytes.substr(0, bytes.size() / 2));
  EXPECT_TRUE(has(error_of([&] { read_all_lines(cut); }), "truncated"));
  const InputError e("a.txt", 7, "5 numbers");
  EXPECT_TRUE(e.file() == "a.txt" && e.line() == 7u && e.what_expected() == "5 numbers");
}

TEST_F(IoTest, MatrixRoundTripAndFormat) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Random(37, 53);  // mantissas in [-1, 1], exponents +-300
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) *= std::pow(10.0, i * 37 % 601 - 300);
  m(0, 0) = 0.0;
  m(1, 1) = 1.00000000049999;  // worst case for 10 digits: just under half a unit
  for (const char* name : {"m.txt", "sub/dir/m.txt.gz"}) {
    const std::string p = (dir_ / name).string();
    write_matrix_text(p, m);
    const double any = std::numeric_limits<double>::max();  // the default bound is 1e30
    const Eigen::MatrixXd back = read_matrix_text(p, 53, any);
    ASSERT_TRUE(back.rows() == 37 && back.cols() == 53);
    for (Eigen::Index i = 0; i < m.size(); ++i) {
      ASSERT_LE(std::abs(back(i) - m(i)), 1e-9 * std::abs(m(i))) << name << " " << i;
    }
    write_matrix_text(p, m, 0);  // shortest round-trip text: exact
    EXPECT_TRUE(read_matrix_text(p, 0, any) == m) << name;
    for (int digits : {10, 3, 0}) {  // as_written: bit for bit what is read back
      write_matrix_text(p, m, digits);
      EXPECT_TRUE(read_matrix_text(p, 0, any) == as_written(m, digits)) << name << " " << digits;
    }
    EXPECT_FALSE(as_written(m) == m);  // 10 digits do not hold a double
  }
  EXPECT_EQ(slurp((dir_ / "sub/dir/m.txt.gz").string()).substr(0, 2), "\x1f\x8b");  // gzip magic
  const Eigen::MatrixXd small = (Eigen::MatrixXd(2, 2) << 1, 0.5, -2.25, 1e-20).finished();
  const std::string p = (dir_ / "small.txt").string();
  write_matrix_text(p, small);
  EXPECT_EQ(slurp(p), "1 0.5\n-2.25 1e-20\n");
  write_matrix_text(p, small * (1.0 / 3.0), 3);
  EXPECT_EQ(slurp(p), "0.333 0.167\n-0.75 3.33e-21\n");
  EXPECT_THROW(write_matrix_text(p, small, 18), std::invalid_argument);
  EXPECT_THROW(write_matrix_text(p, small, -1), std::invalid_argument);
}

TEST_F(IoTest, MatrixReadErrors) {
  const auto read = [](auto p) { read_matrix_text(p); };
  expect_bad(read, "1 2 3 4\n5 6 7 8\n9 10 11\n", 3, "4 numbers");
  expect_bad([](auto p) { read_matrix_text(p, 5); }, "1 2 3 4\n", 1, "5 numbers");
  expect_bad(read, "1 2\n3 4 5\n", 2, "2 numbers");
  expect_bad(read, "1 2\n3 x\n", 2, "2 numbers");
  expect_bad(read, "1 2\n\n3 4\n", 2, "no blank line");
  const Eigen::MatrixXd m = read_matrix_text(gz_file("ok.gz", " 1  2 \n3\t4\n\n  \n"));
  EXPECT_EQ(m, (Eigen::MatrixXd(2, 2) << 1, 2, 3, 4).finished());
  EXPECT_EQ(read_matrix_text(file("e.txt", ""), 9).cols(), 9);
}

TEST_F(IoTest, SodsoPoses) {
  const std::string row = " 1 0 0 0.5 0 1 0 -2 0 0 1 3e1\n";
  const auto poses = read_sodso_poses(file("p.txt", "0" + row + "7" + row + "\n"));
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[1].id, 7);
  EXPECT_EQ(poses[1].T_cam_world.col(3), Eigen::Vector3d(0.5, -2, 30));
  EXPECT_EQ(poses[1].T_cam_world(0, 0), 1.0);
  const auto read = [](auto p) { read_sodso_poses(p); };
  expect_bad(read, "0" + row + "3 1 0 0 0.5 0 1 0 -2 0 0 1\n", 2, "13 numbers");  // truncated
  expect_bad(read, "0" + row.substr(0, row.size() - 1) + " 4\n", 1, "13 numbers");
  expect_bad(read, "0" + row + "5" + row + "5" + row, 3, "keyframe ids in increasing order");
  expect_bad(read, "0" + row + "1 nan 0 0 0 0 1 0 0 0 0 1 0\n", 2, "finite");
  expect_bad(read, "0.5" + row, 1, "13 numbers");
}

TEST_F(IoTest, SodsoPointsSkipClampAndCount) {
  const std::string p =
      file("pts.txt", "0 1 2 3 68.2\n0 nan 2 3 10\n1 1 2 3 300\n1 1 2 3 -4\n2 1 2 3 inf\n");
  PointReadStats stats;
  const auto pts = read_sodso_points(p, &stats);
  ASSERT_EQ(pts.size(), 3u);
  EXPECT_EQ(stats.non_finite_skipped, 2u);
  EXPECT_EQ(stats.intensity_clamped, 2u);
  EXPECT_EQ(pts[0].intensity, 68.2f);
  EXPECT_EQ(pts[0].p_world, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(pts[1].id == 1 && pts[1].intensity == 255.f && pts[2].intensity == 0.f);
  EXPECT_EQ(read_sodso_points(p).size(), 3u);  // stats are optional
  const auto read = [](auto path) { read_sodso_points(path); };
  expect_bad(read, "1 0 0 0 1\n2 0 0 0 1\n1 0 0 0 1\n", 3, "non-decreasing");
  expect_bad(read, "1 0 0 0 1\n2 0 0 0\n", 2, "5 numbers: id x y z intensity");
  expect_bad(read, "1 0 0 0 1 9\n", 1, "5 numbers");
}

// Streamed keyframe by keyframe, a file gives exactly what reading it whole gives (keyframes
// without points, skipped keyframe ids and points after the last asked keyframe included),
// with the same errors at the same lines.
TEST_F(IoTest, SodsoPointsStreamedByKeyframeAreTheWholeFile) {
  const std::string p = file("pts.txt",
                             "0 1 2 3 68.2\n0 nan 2 3 10\n2 1 2 3 300\n2 4 5 6 7\n5 1 2 3 -4\n"
                             "5 7 8 9 1\n9 0 0 1 2\n");
  const std::vector<loopscan::IdPoint> whole = read_sodso_points(p);
  SodsoPointReader reader(p);
  std::vector<loopscan::IdPoint> streamed, part;
  std::vector<std::size_t> sizes;
  for (const int keyframe : {0, 1, 2, 4, 5, 7}) {
    reader.read_until(keyframe, part);
    for (const loopscan::IdPoint& q : part) EXPECT_LE(q.id, keyframe);
    sizes.push_back(part.size());
    streamed.insert(streamed.end(), part.begin(), part.end());
  }
  EXPECT_EQ(sizes, (std::vector<std::size_t>{1, 0, 2, 0, 2, 0}));
  reader.read_until(std::numeric_limits<int>::max(), part);  // the rest
  ASSERT_EQ(part.size(), 1u);
  EXPECT_EQ(part[0].id, 9);
  streamed.insert(streamed.end(), part.begin(), part.end());
  ASSERT_EQ(streamed.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(streamed[i].id, whole[i].id);
    EXPECT_EQ(streamed[i].p_world, whole[i].p_world);
    EXPECT_EQ(streamed[i].intensity, whole[i].intensity);
  }
  EXPECT_EQ(reader.stats().non_finite_skipped, 1u);
  EXPECT_EQ(reader.stats().intensity_clamped, 2u);
  const auto stream = [](auto path) {
    SodsoPointReader r(path);
    std::vector<loopscan::IdPoint> out;
    for (int k = 0; k < 4; ++k) r.read_until(k, out);
  };
  expect_bad(stream, "1 0 0 0 1\n2 0 0 0 1\n1 0 0 0 1\n", 3, "non-decreasing");
  expect_bad(stream, "1 0 0 0 1\n2 0 0 0\n", 2, "5 numbers: id x y z intensity");
}

TEST_F(IoTest, GroundTruth) {
  EXPECT_EQ(parse_gt_format("kitti"), GtFormat::Kitti);
  EXPECT_EQ(parse_gt_format("robotcar"), GtFormat::RobotCar);
  EXPECT_TRUE(has(error_of<std::invalid_argument>([] { parse_gt_format("tum"); }), "'tum'"));
  const std::string kitti = file("k.txt", "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 4 0 1 0 5 0 0 1 6\n");
  EXPECT_EQ(read_kitti_poses(kitti).at(1)(2, 3), 6.0);
  EXPECT_EQ(read_positions(kitti, GtFormat::Kitti), (Positions{{1, 2, 3}, {4, 5, 6}}));
  const auto rc = read_positions(file("rc.txt", "5735000.5 620000.25 -1\n"), GtFormat::RobotCar);
  EXPECT_EQ(rc, (Positions{{5735000.5, 620000.25, -1}}));
  expect_bad([](auto p) { read_kitti_poses(p); }, "1 0 0 1 0 1 0 2 0 0 1\n", 1, "12 numbers");
  expect_bad([](auto p) { read_kitti_poses(p); }, "1 0 0 1 0 1 0 2 0 0 1 inf\n", 1, "finite");
  expect_bad([](auto p) { read_positions(p, GtFormat::RobotCar); }, "1 2 3\n1 2 3 4\n", 2,
             "3 numbers");
}

TEST_F(IoTest, IncomingIds) {
  const std::vector<int> ids = {42, 43, 0, 1000000};
  for (const char* name : {"ids.txt", "ids.txt.gz"}) {
    const std::string p = (dir_ / name).string();
    write_incoming_ids(p, ids);
    EXPECT_EQ(read_incoming_ids(p), ids);
  }
  EXPECT_EQ(slurp((dir_ / "ids.txt").string()), "42\n43\n0\n1000000\n");
  const auto read = [](auto p) { read_incoming_ids(p); };
  expect_bad(read, "1\n2\n3 4\n", 3, "integer");
  expect_bad(read, "-1\n", 1, "non-negative");
}

TEST_F(IoTest, AtomicWrites) {
  const std::string p = (dir_ / "a/b/out.txt").string();
  write_file_atomic(p, "hello\n");
  EXPECT_EQ(slurp(p), "hello\n");
  {
    AtomicWriter w(p);
    w.stream() << "partial";
    EXPECT_TRUE(fs::exists(w.temp_path()));
  }  // not committed: old content stays, temp removed
  EXPECT_EQ(slurp(p), "hello\n");
  const std::string q = (dir_ / "never.txt").string();
  { AtomicWriter w(q); }
  EXPECT_FALSE(fs::exists(q));
  AtomicWriter w(p);
  w.stream() << "new";
  w.commit();
  EXPECT_THROW(w.commit(), std::logic_error);
  EXPECT_EQ(slurp(p), "new");
  for (const auto& entry : fs::recursive_directory_iterator(dir_))
    EXPECT_FALSE(has(entry.path().string(), ".tmp.")) << entry.path();
  const std::string under_file = p + "/x.txt";  // parent is a regular file
  EXPECT_TRUE(
      has(error_of<std::runtime_error>([&] { write_file_atomic(under_file, "x"); }), under_file));
}

TEST(IoFixtureTest, ReadsK06Summer) {
  const fs::path dir = fs::path(loopscan::test::fixture_dir());
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(dir / "poses_history_file.txt"), dir.string());
  const auto path = [&](const char* name) { return (dir / name).string(); };
  const auto poses = read_sodso_poses(path("poses_history_file.txt"));
  ASSERT_EQ(poses.size(), 910u);
  EXPECT_EQ(poses[1].id, 7);
  EXPECT_EQ(poses[1].T_cam_world(2, 3), -8.54463);
  PointReadStats stats;
  const auto pts = read_sodso_points(path("pts_history_file.txt.gz"), &stats);
  EXPECT_EQ(pts.size() + stats.non_finite_skipped, 273000u);
  EXPECT_EQ(pts[0].p_world, Eigen::Vector3d(-19.6860, 1.6439, 30.4797));
  EXPECT_EQ(pts[0].intensity, 68.2f);
  EXPECT_EQ(read_kitti_poses(path("gt.txt")).size(), 1101u);
  EXPECT_EQ(read_positions(path("gt.txt"), GtFormat::Kitti).size(), 1101u);
  const auto ids = read_incoming_ids(path("reference/incoming_id_file.txt"));
  EXPECT_TRUE(ids.size() == 880u && ids.front() == 42) << ids.size();
  const auto sig = read_matrix_text(path("reference/signatures_delight.txt.gz"), 256);
  EXPECT_TRUE(sig.rows() == 14080 && sig.cols() == 256) << sig.rows() << " x " << sig.cols();
}
