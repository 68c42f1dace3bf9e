// Times the authors' C++ (IRVLab/so_dso_place_recognition) per keyframe, one thread, on the
// k06 fixture, with the keyframes loopscan's bench/bench_stages.cpp uses. Not part of the
// CMake build: scripts/bench-authors compiles it against $AUTHORS_SRC (their sources are never
// copied here). Output on stdout: "<stage> <median ms per keyframe> <keyframes>" lines.
//   bench_authors <poses_history_file.txt> <pts_history_file.txt> [repetitions]
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <utility>
#include <vector>

// Their headers, in this order: pts_align.h needs Eigen/Eigenvalues, which SC.h brings in.
#include "place_recognition/generate_signatures/src/SC/SC.h"
// SC.h and M2DP.h both #define numS/numR; the class declarations do not use them.
#undef numS
#undef numR
#include "place_recognition/generate_signatures/src/DELIGHT/DELIGHT.h"
#include "place_recognition/generate_signatures/src/M2DP/M2DP.h"
#include "place_recognition/generate_signatures/src/utils/pts_align.h"
#include "place_recognition/generate_signatures/src/utils/pts_preprocess.h"

namespace {

using Scan = std::vector<std::pair<Eigen::Vector3d, float>>;
constexpr double kRange = 45.0;  // lidarRange, their launch default and the fixture's

// Their pts_preprocess() loop without its file I/O (it reads the files and writes
// incoming_id_file itself): reset test, INIT_FRAME skip, generate_spherical_points. Every 8th
// described keyframe goes to `keep`, as bench_stages.cpp's descriptor inputs. Returns scans.
int imitate(const std::vector<IDPose*>& poses, const std::vector<IDPtIntensity*>& pts,
            bool polar, std::vector<Scan>* keep) {
  std::vector<IDPtIntensity*> nearby;
  Scan scan;
  std::size_t next = 0;
  int from_reset = 0, scans = 0;
  for (IDPose* pose : poses) {
    if (pose->w2c.col(3).norm() < 1.0) {
      from_reset = 0;
      nearby.clear();
    }
    while (next < pts.size() && pts[next]->incoming_id <= pose->incoming_id)
      nearby.push_back(pts[next++]);
    if (from_reset < INIT_FRAME) {
      ++from_reset;
      continue;
    }
    scan.clear();
    generate_spherical_points(pose, nearby, scan, kRange, polar);
    if (keep && scans % 8 == 0) keep->push_back(scan);
    ++scans;
  }
  return scans;
}

// The region test_m2dp.cpp times per keyframe: PCA alignment, then 4 sign-flipped versions.
void m2dp_keyframe(M2DP& m2dp, const Scan& scan, Eigen::MatrixXd& rows) {
  Scan aligned;
  align_points_PCA(scan, aligned);
  int row = 0;
  for (int dx = -1; dx < 2; dx += 2) {
    for (int dy = -1; dy < 2; dy += 2) {
      Scan flipped;
      for (auto& pc : aligned) {
        Eigen::Vector3d p(dx * pc.first[0], dy * pc.first[1], (dx * dy) * pc.first[2]);
        flipped.push_back({p, pc.second});
      }
      Eigen::VectorXd ct, ci;
      m2dp.getSignature(flipped, ct, ci);
      rows.row(row).head(ct.size()) = ct.transpose();
      rows.row(row++).tail(ci.size()) = ci.transpose();
    }
  }
}

double seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s poses_history_file.txt pts_history_file.txt [reps]\n",
                 argv[0]);
    return 2;
  }
  const int reps = argc > 3 ? std::max(1, std::atoi(argv[3])) : 5;
  // generate_spherical_points printf()s a progress line per keyframe: send it to /dev/null
  // (kept in the timing, it is their code) and report on a copy of the real stdout.
  std::fflush(stdout);
  FILE* out = fdopen(dup(STDOUT_FILENO), "w");
  const int devnull = open("/dev/null", O_WRONLY);
  if (!out || devnull < 0 || dup2(devnull, STDOUT_FILENO) < 0) return 1;

  std::vector<IDPose*> poses;
  std::vector<IDPtIntensity*> pts;
  read_poses_pts(argv[1], argv[2], poses, pts);
  if (poses.empty() || pts.empty()) {
    std::fprintf(stderr, "bench_authors: could not read %s / %s\n", argv[1], argv[2]);
    return 1;
  }
  std::vector<Scan> cartesian, polar;  // descriptor inputs, also the warm-up passes
  const int scans = imitate(poses, pts, false, &cartesian);
  imitate(poses, pts, true, &polar);
  std::fprintf(stderr, "bench_authors: %zu keyframes, %zu points, %d scans, %zu described\n",
               poses.size(), pts.size(), scans, cartesian.size());

  auto report = [&](const char* stage, double items, const std::function<void()>& f) {
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) ms.push_back(1e3 * seconds(f) / items);
    std::fprintf(out, "%s %.6g %g\n", stage, median(ms), items);
    std::fflush(out);
  };
  report("imitation_cartesian", scans, [&] { imitate(poses, pts, false, nullptr); });
  report("imitation_polar", scans, [&] { imitate(poses, pts, true, nullptr); });

  // Scan Context on the Cartesian-filtered scans, M2DP and DELIGHT on the polar ones (as the
  // authors' test_*.cpp and the fixture's reference signatures).
  SC sc(kRange);
  report("scan_context", cartesian.size(), [&] {
    for (const Scan& s : cartesian) {
      Eigen::VectorXd structure, intensity;
      sc.getSignature(s, structure, intensity);
      asm volatile("" : : "r"(structure.data()), "r"(intensity.data()) : "memory");
    }
  });
  M2DP m2dp(kRange);
  Eigen::MatrixXd m2dp_rows(4, 2 * m2dp.getSignatureSize());
  report("m2dp", polar.size(), [&] {
    for (const Scan& s : polar) m2dp_keyframe(m2dp, s, m2dp_rows);
  });
  DELIGHT delight;
  report("delight", polar.size(), [&] {
    for (const Scan& s : polar) {
      Eigen::MatrixXd signature;
      delight.getSignature(s, signature);
      asm volatile("" : : "r"(signature.data()) : "memory");
    }
  });
  for (IDPose* p : poses) delete p;
  for (IDPtIntensity* p : pts) delete p;
  return 0;
}
