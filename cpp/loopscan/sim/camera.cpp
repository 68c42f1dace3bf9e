#include "loopscan/sim/camera.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <stdexcept>
#include <utility>

namespace loopscan::sim {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") + 1 - first);
}

[[noreturn]] void fail(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

// Value text and line number of every top-level `key: value` line.
std::map<std::string, std::pair<std::string, int>> read_keys(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open camera settings '" + path + "'");
  std::map<std::string, std::pair<std::string, int>> keys;
  std::string raw;
  for (int line = 1; std::getline(in, raw); ++line) {
    const std::string text = trim(raw);
    if (text.empty() || text[0] == '%' || text[0] == '#' || text.rfind("---", 0) == 0) continue;
    // Indented lines belong to nested yaml maps (e.g. opencv matrices) we do not need.
    if (raw[0] == ' ' || raw[0] == '\t') continue;
    const auto colon = text.find(':');
    if (colon == std::string::npos || colon == 0) fail(path, line, "expected 'key: value'");
    std::string value = trim(text.substr(colon + 1));
    if (const auto hash = value.find('#'); hash != std::string::npos)
      value = trim(value.substr(0, hash));
    keys[trim(text.substr(0, colon))] = {value, line};
  }
  return keys;
}

class Settings {
 public:
  explicit Settings(const std::string& path) : path_(path), keys_(read_keys(path)) {}

  double number(const std::string& key) const {
    const auto& [text, line] = find(key);
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno != 0 || !std::isfinite(v)) {
      fail(path_, line, "bad number '" + text + "' for " + key);
    }
    return v;
  }

  double positive(const std::string& key) const {
    const double v = number(key);
    if (v <= 0.0) fail(path_, find(key).second, key + " must be positive");
    return v;
  }

  int positive_int(const std::string& key) const {
    const double v = positive(key);
    if (v != std::floor(v) || v > 1e6) fail(path_, find(key).second, key + " must be an integer");
    return static_cast<int>(v);
  }

 private:
  const std::pair<std::string, int>& find(const std::string& key) const {
    const auto it = keys_.find(key);
    if (it == keys_.end()) throw std::runtime_error("missing key " + key + " in '" + path_ + "'");
    return it->second;
  }

  std::string path_;
  std::map<std::string, std::pair<std::string, int>> keys_;
};

}  // namespace

StereoCamera StereoCamera::read_orbslam_yaml(const std::string& path) {
  const Settings s(path);
  StereoCamera c;
  c.fx = s.positive("Camera.fx");
  c.fy = s.positive("Camera.fy");
  c.cx = s.number("Camera.cx");
  c.cy = s.number("Camera.cy");
  c.width = s.positive_int("Camera.width");
  c.height = s.positive_int("Camera.height");
  c.bf = s.positive("Camera.bf");
  return c;
}

bool StereoCamera::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& pixel) const {
  if (!(p_cam.z() > 0.0)) return false;
  pixel = {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  return pixel.x() >= -0.5 && pixel.x() < width - 0.5 && pixel.y() >= -0.5 &&
         pixel.y() < height - 0.5;
}

Eigen::Vector3d StereoCamera::ray(double u, double v) const {
  return Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0).normalized();
}

}  // namespace loopscan::sim
