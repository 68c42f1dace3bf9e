#include "loopscan/io/vo_files.hpp"

#include <cstdio>
#include <stdexcept>

#include "loopscan/io/text_file_writer.hpp"

namespace loopscan::io {
namespace {

// Appends printf-formatted text to a buffer flushed to the writer in large blocks.
class Buffer {
 public:
  explicit Buffer(const std::string& path) : out_(path) {}
  template <typename... Args>
  void printf(const char* format, Args... args) {
    char line[512];
    const int n = std::snprintf(line, sizeof line, format, args...);
    text_.append(line, static_cast<std::size_t>(n));
    if (text_.size() > (1u << 20)) flush();
  }
  void commit() {
    flush();
    out_.commit();
  }

 private:
  void flush() {
    out_.write(text_);
    text_.clear();
  }
  TextFileWriter out_;
  std::string text_;
};

void print_3x4(Buffer& b, const Eigen::Matrix<double, 3, 4>& m) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) b.printf(r + c == 0 ? "%.9g" : " %.9g", m(r, c));
  }
  b.printf("\n");
}

}  // namespace

void write_sodso_poses(const std::string& path, const std::vector<KeyframePose>& poses) {
  Buffer b(path);
  for (const KeyframePose& k : poses) {
    b.printf("%d ", k.id);
    print_3x4(b, k.T_cam_world);
  }
  b.commit();
}

void write_sodso_points(const std::string& path, const std::vector<IdPoint>& points) {
  Buffer b(path);
  for (const IdPoint& p : points) {
    b.printf("%d %.4f %.4f %.4f %.1f\n", p.id, p.p_world.x(), p.p_world.y(), p.p_world.z(),
             static_cast<double>(p.intensity));
  }
  b.commit();
}

void write_kitti_poses(const std::string& path,
                       const std::vector<Eigen::Matrix<double, 3, 4>>& T_world_cam) {
  Buffer b(path);
  for (const auto& m : T_world_cam) print_3x4(b, m);
  b.commit();
}

void write_tum_trajectory(const std::string& path, const std::vector<double>& times,
                          const std::vector<Eigen::Isometry3d>& T_world_body) {
  if (times.size() != T_world_body.size())
    throw std::invalid_argument("write_tum_trajectory: one time per pose");
  Buffer b(path);
  b.printf("# timestamp tx ty tz qx qy qz qw\n");
  for (std::size_t i = 0; i < times.size(); ++i) {
    const Eigen::Quaterniond q(T_world_body[i].linear());
    const Eigen::Vector3d t = T_world_body[i].translation();
    b.printf("%.9f %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", times[i], t.x(), t.y(), t.z(), q.x(),
             q.y(), q.z(), q.w());
  }
  b.commit();
}

void write_gps(const std::string& path, const std::vector<Eigen::Vector3d>& ned) {
  Buffer b(path);
  for (const auto& r : ned) b.printf("%.6f %.6f %.6f\n", r.x(), r.y(), r.z());
  b.commit();
}

}  // namespace loopscan::io
