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
#include "seed_inputs.hpp"

namespace loopscan::fuzz {
namespace {

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
  t.push_back(one_file("camera_yaml", "camera.yaml", {camera_yaml()},
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
