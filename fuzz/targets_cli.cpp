// The CLI commands over mutated inputs, whole: describe (SO-DSO files), evaluate (a describe
// output and its ground truth), pairs, db query, render (camera yaml) and vo (a KITTI-layout
// sequence). Whatever a reader accepts then runs through imitation, descriptors, matching,
// the VO: every exit code must be 0 or 2.
#include <sstream>

#include <opencv2/core.hpp>

#include "fuzz_target.hpp"
#include "loopscan/core/database/database.hpp"
#include "loopscan/io/database_file.hpp"
#include "seed_inputs.hpp"

namespace loopscan::fuzz {
namespace {

using Args = std::vector<std::string>;

// One target per file of `seed` that the command reads; `make` gives the arguments.
void add_per_file(std::vector<Target>& out, const std::string& name, const Files& seed,
                  const std::vector<std::string>& files,
                  std::function<Args(const std::string&, const std::string&, long)> make) {
  for (const std::string& f : files) {
    Target t;
    t.name = name + ":" + f;
    const auto ends_with = [&](const char* e) {
      const std::string ext = e;
      return f.size() > ext.size() && f.compare(f.size() - ext.size(), ext.size(), ext) == 0;
    };
    t.format = ends_with(".png") || ends_with(".db") ? Format::Binary : Format::Text;
    t.png_chunks = ends_with(".png");
    t.trailing_crc = ends_with(".db");
    t.mutated_file = f;
    t.seeds.push_back(seed);
    t.command = make;
    out.push_back(std::move(t));
  }
}

std::string describe_output_ids(int n) {
  std::ostringstream s;
  for (int i = 0; i < n; ++i) s << 3 + 5 * i << '\n';
  return s.str();
}

std::string identity_frames(int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += "1 0 0 0 1 0 0 0 1\n";
  return s;
}

std::string scan_context_db() {
  Database db;
  for (int i = 0; i < 3; ++i) {
    Signature s = Signature::Zero(1, 2400);
    for (int k = i; k < 2400; k += 7) s(0, k) = 0.25 * (k % 5);
    db.add({0, 3 + 5 * i}, {s}, Pose3x4::Identity());
  }
  return bytes_written_by([&](const std::string& p) { io::save_database(db, p); });
}

}  // namespace

std::vector<Target> cli_targets() {
  std::vector<Target> t;
  const char* methods[] = {"sc", "m2dp", "delight"};
  add_per_file(
      t, "describe", {{"poses.txt", poses_text(true, 36)}, {"pts.txt", points_text(36, 12)}},
      {"poses.txt", "pts.txt"}, [methods](const std::string& d, const std::string& o, long v) {
        return Args{"describe", "--method",     methods[v % 3], "--poses", d + "/poses.txt",
                    "--points", d + "/pts.txt", "--out",        o};
      });
  const Files described = {{"signatures.txt", matrix_text(4, 2400)},
                           {"incoming_id_file.txt", describe_output_ids(4)},
                           {"frames.txt", identity_frames(4)},
                           {"gt.txt", poses_text(false, 30)}};
  Files evaluated = described;
  evaluated["protocol.yaml"] =
      "mode: default\nevaluation:\n  fusion: fused\n  same_session:\n    mask: 1\n"
      "    threshold_m: 10\n";
  add_per_file(t, "evaluate", evaluated,
               {"signatures.txt", "incoming_id_file.txt", "frames.txt", "gt.txt", "protocol.yaml"},
               [](const std::string& d, const std::string& o, long) {
                 return Args{"evaluate", "--method",    "sc",       "--signatures",       d,
                             "--gt",     d + "/gt.txt", "--config", d + "/protocol.yaml", "--out",
                             o};
               });
  add_per_file(t, "pairs", {{"pairs.txt", "0.9 1\n0.75 0\n0.5 1\n0.125 0\n"}}, {"pairs.txt"},
               [](const std::string& d, const std::string& o, long) {
                 return Args{"pairs", "--scores", d + "/pairs.txt", "--out", o};
               });
  Files query = {{"map.db", scan_context_db()}};
  for (const auto& [name, bytes] : described) query["q/" + name] = bytes;
  add_per_file(t, "db query", query, {"map.db", "q/signatures.txt"},
               [](const std::string& d, const std::string& o, long v) {
                 Args a{"db", "query", "--db", d + "/map.db", "--signatures", d + "/q", "--out", o};
                 if (v % 2) a.push_back("--exact");
                 return a;
               });
  add_per_file(t, "render", {{"camera.yaml", camera_yaml()}}, {"camera.yaml"},
               [](const std::string& d, const std::string& o, long) {
                 return Args{
                     "render", "--trajectory", "builtin:short",    "--frames", "1", "--scale",
                     "0.05",   "--calib",      d + "/camera.yaml", "--out",    o};
               });
  Files sequence = {{"calib.txt", kCalib},
                    {"times.txt", "0\n0.1\n0.2\n0.3\n"},
                    {"segments.yaml", "odometry_metrics:\n  segment_lengths_m: [1]\n"}};
  for (int i = 0; i < 4; ++i) {
    char name[64];
    for (int cam = 0; cam < 2; ++cam) {
      std::snprintf(name, sizeof name, "image_%d/%06d.png", cam, i);
      sequence[name] = image_bytes(".png", CV_8UC1, 96, 40);
    }
  }
  add_per_file(t, "vo", sequence, {"calib.txt", "times.txt", "image_0/000001.png"},
               [](const std::string& d, const std::string& o, long) {
                 return Args{"vo",      "--kitti", d, "--config", d + "/segments.yaml",
                             "--quiet", "--out",   o};
               });
  return t;
}

}  // namespace loopscan::fuzz
