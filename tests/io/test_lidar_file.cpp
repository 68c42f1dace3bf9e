// LiDAR scan files: the same points through .bin, .bin.gz, PCD (ascii, binary) and PLY (ascii,
// binary), and every malformed variant rejected with an error naming the file.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/lidar_file.hpp"
#include "support/input_errors.hpp"
#include "support/test_support.hpp"

namespace loopscan::io {
namespace {
namespace fs = std::filesystem;

struct P {
  float x, y, z, r;
};

std::vector<P> points(int n) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-40.f, 40.f), r(0.f, 1.f);
  std::vector<P> out(n);
  for (P& p : out) p = {u(rng), u(rng), u(rng) / 10.f, r(rng)};
  return out;
}

fs::path dir() {
  const fs::path d = test::temp_path("lidar_files");
  fs::create_directories(d);
  return d;
}

std::string write(const std::string& name, const std::string& bytes) {
  const fs::path p = dir() / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

std::string raw(const std::vector<P>& ps) {
  return std::string(reinterpret_cast<const char*>(ps.data()), ps.size() * sizeof(P));
}

std::string ascii_rows(const std::vector<P>& ps) {
  std::string s;
  char line[128];
  for (const P& p : ps) {
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g\n", p.x, p.y, p.z, p.r);
    s += line;
  }
  return s;
}

void expect_same(const Cloud& c, const std::vector<P>& ps, const std::string& what) {
  ASSERT_EQ(c.size(), ps.size()) << what;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    ASSERT_FLOAT_EQ(static_cast<float>(c[i].p.x()), ps[i].x) << what << " point " << i;
    ASSERT_FLOAT_EQ(static_cast<float>(c[i].p.z()), ps[i].z) << what << " point " << i;
    ASSERT_FLOAT_EQ(c[i].intensity, ps[i].r) << what << " point " << i;
  }
}

void expect_error(const std::string& path, const std::string& fragment) {
  test::expect_input_error([](const std::string& p) { read_lidar_scan(p); }, path, fragment);
}

TEST(LidarFile, EveryFormatGivesTheSamePoints) {
  const std::vector<P> ps = points(500);
  expect_same(read_lidar_scan(write("a.bin", raw(ps))), ps, "bin");
  const std::string gz = (dir() / "a.bin.gz").string();
  gzFile f = gzopen(gz.c_str(), "wb");
  gzwrite(f, raw(ps).data(), static_cast<unsigned>(ps.size() * sizeof(P)));
  gzclose(f);
  expect_same(read_lidar_scan(gz), ps, "bin.gz");
  const std::string n = std::to_string(ps.size());
  const std::string pcd =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\n"
      "TYPE F F F F\nCOUNT 1 1 1 1\nWIDTH " +
      n + "\nHEIGHT 1\nPOINTS " + n;
  expect_same(read_lidar_scan(write("a.pcd", pcd + "\nDATA ascii\n" + ascii_rows(ps))), ps,
              "pcd ascii");
  expect_same(read_lidar_scan(write("b.pcd", pcd + "\nDATA binary\n" + raw(ps))), ps, "pcd binary");
  const std::string ply = "element vertex " + n +
                          "\nproperty float x\nproperty float y\nproperty float z\n"
                          "property float intensity\nelement face 0\n"
                          "property list uchar int vertex_indices\nend_header\n";
  expect_same(read_lidar_scan(write("a.ply", "ply\nformat ascii 1.0\n" + ply + ascii_rows(ps))), ps,
              "ply ascii");
  expect_same(
      read_lidar_scan(write("b.ply", "ply\nformat binary_little_endian 1.0\n" + ply + raw(ps))), ps,
      "ply binary");
}

TEST(LidarFile, MalformedFilesNameTheFileAndTheProblem) {
  const std::vector<P> ps = points(10);
  expect_error(write("short.bin", raw(ps).substr(0, 100)), "multiple of 16");
  expect_error(write("noz.pcd", "FIELDS x y\nSIZE 4 4\nTYPE F F\nPOINTS 1\nDATA ascii\n1 2\n"),
               "fields x, y and z");
  expect_error(write("comp.pcd",
                     "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\n"
                     "DATA binary_compressed\n"),
               "binary_compressed");
  expect_error(write("trunc.pcd",
                     "FIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
                     "POINTS 10\nDATA binary\n" +
                         raw(ps).substr(0, 50)),
               "file ends early");
  expect_error(write("rows.pcd",
                     "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 3\nDATA ascii\n"
                     "1 2 3\n4 5\n"),
               "rows.pcd:7");
  expect_error(write("big.ply",
                     "ply\nformat binary_big_endian 1.0\nelement vertex 1\n"
                     "property float x\nend_header\n"),
               "binary_little_endian");
  expect_error(write("nonl.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 2\nDATA binary"),
               "file ends early");
  expect_error(write("nohdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), "end_header");
  expect_error(write("a.xyz", "1 2 3\n"), "*.bin");
  expect_error((dir() / "missing.bin").string(), "readable");
}

TEST(LidarFile, FoldersExpandToTheirScansInNameOrder) {
  const fs::path d = dir() / "folder";
  fs::remove_all(d);
  fs::create_directories(d);
  for (const char* name : {"2.bin", "1.pcd", "notes.txt", "0.ply"}) std::ofstream(d / name) << "";
  const std::vector<std::string> files = lidar_scan_files({d.string()});
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(fs::path(files[0]).filename(), "0.ply");
  EXPECT_EQ(fs::path(files[2]).filename(), "2.bin");
  EXPECT_THROW(lidar_scan_files({(d / "nope").string()}), InputError);
}

}  // namespace
}  // namespace loopscan::io
