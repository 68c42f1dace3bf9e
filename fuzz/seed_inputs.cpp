#include "seed_inputs.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "fuzz_target.hpp"
#include "loopscan/io/text_file_writer.hpp"
#include "loopscan/io/vocabulary_file.hpp"

namespace loopscan::fuzz {
namespace {

std::string rotation_row(double yaw, double tx, double ty, double tz) {
  char buf[256];
  const double c = std::cos(yaw), s = std::sin(yaw);
  std::snprintf(buf, sizeof buf, "%.9g 0 %.9g %.9g 0 1 0 %.9g %.9g 0 %.9g %.9g", c, s, tx, ty, -s,
                c, tz);
  return buf;
}

}  // namespace

std::string poses_text(bool with_ids, int n) {
  std::ostringstream s;
  for (int i = 0; i < n; ++i) {
    if (with_ids) s << 2 * i << ' ';
    s << rotation_row(0.01 * i, 0.1 * i, -0.02 * i, 1.3 * i) << '\n';
  }
  return s.str();
}

std::string points_text(int keyframes, int per_keyframe) {
  std::ostringstream s;
  for (int k = 0; k < keyframes; ++k) {
    for (int j = 0; j < per_keyframe; ++j) {
      s << 2 * k << ' ' << (j % 2 ? -7.5 : 6.25) << ' ' << -0.1 * (j % 9) << ' ' << 1.3 * k + j
        << ' ' << (13 * j) % 256 << '\n';
    }
  }
  return s.str();
}

std::string gzip(const std::string& text) {  // TextFileWriter compresses for a ".gz" path
  return bytes_written_by([&](const std::string& p) {
    io::TextFileWriter w(p + ".gz");
    w.write(text);
    w.commit();
    std::filesystem::rename(p + ".gz", p);
  });
}

std::string matrix_text(int rows, int cols) {
  std::ostringstream s;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) s << (c ? " " : "") << ((r * 31 + c * 7) % 11) * 0.125;
    s << '\n';
  }
  return s.str();
}

const std::string kCalib =
    "P0: 718.856 0 607.1928 0 0 718.856 185.2157 0 0 0 1 0\n"
    "P1: 718.856 0 607.1928 -386.1448 0 718.856 185.2157 0 0 0 1 0\n"
    "P2: 718.856 0 607.1928 45.38225 0 718.856 185.2157 -0.1130887 0 0 1 0.003779761\n"
    "P3: 718.856 0 607.1928 -337.2877 0 718.856 185.2157 2.369057 0 0 1 0.004915215\n"
    "Tr: -0.001857739 -0.9999659 -0.008039975 -0.004784029 -0.006481465 0.008051860 -0.9999466 "
    "-0.07337429 0.9999773 -0.001805528 -0.006496203 -0.3339968\n";

io::VocabularyData small_vocabulary(int branching) {
  io::VocabularyData v;
  v.branching = branching;
  v.depth = 2;
  const int nodes = branching * (branching + 1);  // root's children and theirs (root implicit)
  for (int i = 0; i < nodes; ++i) {
    io::VocabularyRecord r;
    r.parent = i < branching ? 0 : 1 + (i - branching) / branching;
    r.leaf = i >= branching;
    for (int b = 0; b < 32; ++b) r.descriptor[b] = static_cast<std::uint8_t>(i * 37 + b * 11);
    r.weight = r.leaf ? 0.25f * (i % 4 + 1) : 0.f;
    v.nodes.push_back(r);
  }
  return v;
}

std::string vocabulary_text() {
  const io::VocabularyData v = small_vocabulary(3);
  return bytes_written_by([&](const std::string& p) { io::write_orbvoc_text(p, v); });
}

std::string camera_yaml() {
  return "%YAML:1.0\nCamera.fx: 707.0912\nCamera.fy: 707.0912\nCamera.cx: 601.8873\n"
         "Camera.cy: 183.1104\nCamera.width: 1241\nCamera.height: 376\n"
         "Camera.bf: 379.8145\nLeftMatrix: !!opencv-matrix\n   rows: 3\n";
}

std::string image_bytes(const char* ext, int type, int width, int height) {
  cv::Mat m(height, width, type);
  cv::randu(m, 0, CV_MAT_DEPTH(type) == CV_16U ? 65535 : 255);
  std::vector<unsigned char> buf;
  cv::imencode(ext, m, buf);
  return std::string(buf.begin(), buf.end());
}

}  // namespace loopscan::fuzz
