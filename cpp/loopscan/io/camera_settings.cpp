#include "loopscan/io/camera_settings.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"

namespace loopscan::io {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank_char(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank_char(s.back())) s.remove_suffix(1);
  return s;
}

// Value text and line number of every top-level `key: value` line.
class FlatYaml {
 public:
  explicit FlatYaml(const std::string& path) : path_(path) {
    LineReader reader(path);
    std::string_view raw;
    while (reader.next(raw)) {
      const std::string_view text = trim(raw);
      if (text.empty() || text[0] == '%' || text[0] == '#' || text.substr(0, 3) == "---") continue;
      // Indented lines belong to nested maps (e.g. OpenCV matrices) that are not needed here.
      if (raw[0] == ' ' || raw[0] == '\t') continue;
      const auto colon = text.find(':');
      if (colon == std::string_view::npos || colon == 0) {
        throw InputError(path, reader.line_number(), "a `key: value` line");
      }
      std::string_view value = trim(text.substr(colon + 1));
      if (const auto hash = value.find('#'); hash != std::string_view::npos) {
        value = trim(value.substr(0, hash));
      }
      keys_[std::string(trim(text.substr(0, colon)))] = {std::string(value), reader.line_number()};
    }
  }

  double number(const std::string& key, double lo, double hi) const {
    const auto& [text, line] = find(key);
    double v = 0;
    if (!parse_number(text, v) || !(v >= lo && v <= hi)) {
      throw InputError(
          path_, line,
          key + ": a number in [" + shown(lo) + ", " + shown(hi) + "] (found '" + text + "')");
    }
    return v;
  }

  int whole(const std::string& key, int lo, int hi) const {
    const double v = number(key, lo, hi);
    if (v != std::floor(v)) throw InputError(path_, find(key).second, key + ": a whole number");
    return static_cast<int>(v);
  }

 private:
  static std::string shown(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }
  const std::pair<std::string, std::size_t>& find(const std::string& key) const {
    const auto it = keys_.find(key);
    if (it == keys_.end()) throw InputError(path_, 0, "a line `" + key + ": <value>`");
    return it->second;
  }

  std::string path_;
  std::map<std::string, std::pair<std::string, std::size_t>> keys_;
};

}  // namespace

StereoSettings read_orbslam_stereo(const std::string& path) {
  const FlatYaml yaml(path);
  // The bounds of the KITTI calibration reader: focal lengths 1..1e5 px, baselines up to 100 m.
  StereoSettings s;
  s.fx = yaml.number("Camera.fx", 1, 1e5);
  s.fy = yaml.number("Camera.fy", 1, 1e5);
  s.cx = yaml.number("Camera.cx", -1e5, 1e5);
  s.cy = yaml.number("Camera.cy", -1e5, 1e5);
  s.width = yaml.whole("Camera.width", 1, limits::kMaxImageSide);
  s.height = yaml.whole("Camera.height", 1, limits::kMaxImageSide);
  if (std::int64_t(s.width) * s.height > limits::kMaxImagePixels) {
    throw InputError(path, 0,
                     "an image of at most " + std::to_string(limits::kMaxImagePixels) +
                         " pixels (Camera.width x Camera.height)");
  }
  s.bf = yaml.number("Camera.bf", 1e-3, 1e7);
  return s;
}

}  // namespace loopscan::io
