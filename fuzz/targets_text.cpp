// The text readers: SO-DSO history files (plain and gzip), ground truth, keyframe ids,
// signature matrices and whole signature sets, KITTI calibration and sequences, BoW vectors,
// ORBvoc.txt, pairwise score files, camera yaml.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "fuzz_target.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/io/bow_file.hpp"
#include "loopscan/io/camera_settings.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/kitti_sequence.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/score_labels.hpp"
#include "loopscan/io/signature_set.hpp"
#include "loopscan/io/sodso.hpp"
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

std::string vocabulary_text() {
  io::VocabularyData v;
  v.branching = 3;
  v.depth = 2;
  for (int i = 0; i < 12; ++i) {
    io::VocabularyRecord r;
    r.parent = i < 3 ? 0 : 1 + (i - 3) / 3;
    r.leaf = i >= 3;
    for (int b = 0; b < 32; ++b) r.descriptor[b] = static_cast<std::uint8_t>(i * 37 + b * 11);
    r.weight = i >= 3 ? 0.25f * (i % 4 + 1) : 0.f;
    v.nodes.push_back(r);
  }
  return bytes_written_by([&](const std::string& p) { io::write_orbvoc_text(p, v); });
}

Target one_file(const std::string& name, const std::string& file, std::vector<std::string> seeds,
                std::function<void(const std::string&)> read_file) {
  return single_file(name, file, Format::Text, std::move(seeds), std::move(read_file));
}

}  // namespace

std::vector<Target> text_targets() {
  std::vector<Target> t;
  t.push_back(one_file("sodso_poses", "poses.txt", {poses_text(true, 40)},
                       [](const std::string& p) { io::read_sodso_poses(p); }));
  t.push_back(one_file("sodso_points", "pts.txt", {points_text(12, 20)},
                       [](const std::string& p) { io::read_sodso_points(p); }));
  Target gz = one_file("sodso_points_gz", "pts.txt.gz", {gzip(points_text(12, 20))},
                       [](const std::string& p) { io::read_sodso_points(p); });
  gz.format = Format::Binary;
  t.push_back(gz);
  t.push_back(one_file("kitti_poses", "gt.txt", {poses_text(false, 30)},
                       [](const std::string& p) { io::read_kitti_poses(p); }));
  t.push_back(
      one_file("robotcar_gps", "gps.txt", {"5735000.25 620000.5 -1.5\n5735001 620000.75 -1.5\n"},
               [](const std::string& p) { io::read_positions(p, io::GtFormat::RobotCar); }));
  t.push_back(one_file("incoming_ids", "ids.txt", {"30\n31\n33\n40\n41\n"},
                       [](const std::string& p) { io::read_incoming_ids(p); }));
  t.push_back(one_file("matrix_text", "signatures.txt", {matrix_text(6, 60)},
                       [](const std::string& p) { io::read_matrix_text(p); }));
  t.push_back(one_file("kitti_calib", "calib.txt", {kCalib},
                       [](const std::string& p) { io::read_kitti_calib(p); }));
  t.push_back(one_file("bow_vectors", "bow.txt", {"0 0.25 7 0.5 12 0.25\n\n3 1\n"},
                       [](const std::string& p) { io::read_bow_vectors(p); }));
  t.push_back(one_file("orbvoc_text", "ORBvoc.txt", {vocabulary_text()},
                       [](const std::string& p) { baselines::read_vocabulary(p); }));
  t.push_back(one_file("score_labels", "pairs.txt", {"0.9 1\n0.75 0\n0.5 1\n0.125 0\n"},
                       [](const std::string& p) { io::read_score_labels(p); }));
  t.push_back(one_file("camera_yaml", "camera.yaml",
                       {"%YAML:1.0\nCamera.fx: 707.0912\nCamera.fy: 707.0912\nCamera.cx: 601.8873\n"
                        "Camera.cy: 183.1104\nCamera.width: 1241\nCamera.height: 376\n"
                        "Camera.bf: 379.8145\nLeftMatrix: !!opencv-matrix\n   rows: 3\n"},
                       [](const std::string& p) { io::read_orbslam_stereo(p); }));
  // A describe output (signatures, ids, frames read together); each case mutates one file.
  for (const char* file : {"signatures.txt", "incoming_id_file.txt", "frames.txt"}) {
    Target set;
    set.name = std::string("signature_set:") + file;
    set.mutated_file = file;
    set.seeds.push_back({{"signatures.txt", matrix_text(2, 2400)},
                         {"incoming_id_file.txt", "30\n31\n"},
                         {"frames.txt", "1 0 0 0 1 0 0 0 1\n0 0 1 0 1 0 -1 0 0\n"}});
    set.read = [](const std::string& dir) { io::load_signature_set(dir, Method::ScanContext); };
    t.push_back(set);
  }
  // A KITTI sequence (calibration, times; images only need to exist to be opened).
  for (const char* file : {"calib.txt", "times.txt"}) {
    Target seq;
    seq.name = std::string("kitti_sequence:") + file;
    seq.mutated_file = file;
    Files f = {{"calib.txt", kCalib}, {"times.txt", "0.0\n1.036e-01\n2.072e-01\n"}};
    for (int i = 0; i < 3; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "image_0/%06d.png", i);
      f[name] = "";
      name[6] = '1';
      f[name] = "";
    }
    seq.seeds.push_back(f);
    seq.read = [](const std::string& dir) { io::open_kitti_sequence(dir); };
    t.push_back(seq);
  }
  return t;
}

}  // namespace loopscan::fuzz
