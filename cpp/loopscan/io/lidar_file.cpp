#include "loopscan/io/lidar_file.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/file_names.hpp"
#include "loopscan/io/limits.hpp"

namespace loopscan::io {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kMaxScanBytes = std::size_t{1} << 30;  // 67M KITTI points

// The whole file, inflated when gzip-compressed (zlib passes plain files through).
std::string file_bytes(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw InputError(path, 0, "a readable file");
  std::string out;
  char buf[1 << 16];
  for (;;) {
    const int n = gzread(f, buf, sizeof buf);
    if (n < 0) {
      gzclose(f);
      throw InputError(path, InputError::Byte{out.size()}, "corrupt or truncated gzip data");
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
    if (out.size() > kMaxScanBytes) {
      gzclose(f);
      throw InputError(path, 0, "a scan of at most 1 GiB");
    }
  }
  gzclose(f);
  return out;
}

void add_point(Cloud& cloud, double x, double y, double z, double intensity,
               LidarReadStats& stats) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) ||
      std::max({std::abs(x), std::abs(y), std::abs(z)}) > limits::kMaxCoordinateM) {
    ++stats.non_finite_skipped;
    return;
  }
  cloud.push_back({{x, y, z}, std::isfinite(intensity) ? static_cast<float>(intensity) : 0.f});
}

Cloud read_bin(const std::string& path, const std::string& bytes, LidarReadStats& stats) {
  if (bytes.size() % 16 != 0) {
    throw InputError(path, InputError::Byte{bytes.size() - bytes.size() % 16},
                     "a size that is a multiple of 16 bytes (float32 x y z reflectance per "
                     "point), found " +
                         std::to_string(bytes.size()) + " bytes");
  }
  Cloud cloud;
  cloud.reserve(bytes.size() / 16);
  float p[4];
  for (std::size_t at = 0; at < bytes.size(); at += 16) {
    std::memcpy(p, bytes.data() + at, 16);
    add_point(cloud, p[0], p[1], p[2], p[3], stats);
  }
  stats.has_intensity = true;
  return cloud;
}

// One field of a PCD / PLY record: byte offset, size, kind ('F' float, 'U' unsigned, 'I' int).
struct Field {
  std::string name;
  std::size_t offset = 0, size = 4;
  char kind = 'F';
};

double field_value(const char* record, const Field& f) {
  unsigned char b[8] = {};
  std::memcpy(b, record + f.offset, f.size);
  if (f.kind == 'F') {
    if (f.size == 8) {
      double v;
      std::memcpy(&v, b, 8);
      return v;
    }
    float v;
    std::memcpy(&v, b, 4);
    return v;
  }
  std::uint64_t u = 0;
  for (std::size_t k = 0; k < f.size; ++k) u |= std::uint64_t(b[k]) << (8 * k);
  if (f.kind == 'U') return static_cast<double>(u);
  const std::uint64_t sign = std::uint64_t{1} << (8 * f.size - 1);
  return static_cast<double>(static_cast<std::int64_t>((u ^ sign) - sign));
}

// Indices of x, y, z and the intensity-like field (-1 when absent).
std::array<int, 4> xyzi(const std::string& path, std::size_t line,
                        const std::vector<Field>& fields) {
  std::array<int, 4> idx = {-1, -1, -1, -1};
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const std::string& n = fields[k].name;
    const int i = n == "x"                                                                   ? 0
                  : n == "y"                                                                 ? 1
                  : n == "z"                                                                 ? 2
                  : (n == "intensity" || n == "reflectance" || n == "remission" || n == "i") ? 3
                                                                                             : -1;
    if (i >= 0 && idx[i] < 0) idx[i] = static_cast<int>(k);
  }
  if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) throw InputError(path, line, "fields x, y and z");
  return idx;
}

// Points of a binary body (little endian, `stride` bytes a record) or an ascii one.
Cloud read_body(const std::string& path, const std::string& bytes, std::size_t body, std::size_t n,
                const std::vector<Field>& fields, std::size_t stride, bool binary,
                std::size_t header_lines, LidarReadStats& stats) {
  body = std::min(body, bytes.size());  // a header ending without a newline
  const std::array<int, 4> idx = xyzi(path, header_lines, fields);
  stats.has_intensity = idx[3] >= 0;
  Cloud cloud;
  cloud.reserve(std::min<std::size_t>(n, bytes.size() / 12 + 1));
  if (binary) {
    if (n > (bytes.size() - body) / std::max<std::size_t>(stride, 1)) {
      throw InputError(path, InputError::Byte{bytes.size()},
                       std::to_string(n) + " points of " + std::to_string(stride) +
                           " bytes after the header, file ends early");
    }
    for (std::size_t i = 0; i < n; ++i) {
      const char* r = bytes.data() + body + i * stride;
      add_point(cloud, field_value(r, fields[idx[0]]), field_value(r, fields[idx[1]]),
                field_value(r, fields[idx[2]]), idx[3] >= 0 ? field_value(r, fields[idx[3]]) : 0,
                stats);
    }
    return cloud;
  }
  std::istringstream in(bytes.substr(body));
  std::string row;
  std::vector<double> v(fields.size());
  for (std::size_t i = 0; i < n; ++i) {
    std::istringstream cells(std::getline(in, row) ? row : std::string());
    for (double& x : v) {
      if (!(cells >> x))
        throw InputError(path, header_lines + i + 1,
                         std::to_string(fields.size()) + " numbers (one point; " +
                             std::to_string(n) + " points announced)");
    }
    add_point(cloud, v[idx[0]], v[idx[1]], v[idx[2]], idx[3] >= 0 ? v[idx[3]] : 0, stats);
  }
  return cloud;
}

Cloud read_pcd(const std::string& path, const std::string& bytes, LidarReadStats& stats) {
  std::vector<Field> fields;
  std::vector<std::size_t> counts;
  std::size_t at = 0, line = 0, points = 0;
  while (at < bytes.size()) {
    const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
    std::istringstream words(bytes.substr(at, end - at));
    at = end + 1;
    ++line;
    std::string key;
    if (!(words >> key) || key[0] == '#') continue;
    std::string w;
    if (key == "FIELDS") {
      while (words >> w) fields.push_back({w});
    } else if (key == "SIZE" || key == "TYPE" || key == "COUNT") {
      for (std::size_t k = 0; words >> w; ++k) {
        if (k >= fields.size()) throw InputError(path, line, key + " per field of FIELDS");
        if (key == "SIZE") fields[k].size = std::strtoul(w.c_str(), nullptr, 10);
        if (key == "TYPE") fields[k].kind = w[0];
        if (key == "COUNT") counts.push_back(std::strtoul(w.c_str(), nullptr, 10));
      }
    } else if (key == "POINTS") {
      words >> points;
    } else if (key == "DATA") {
      words >> w;
      if (w != "ascii" && w != "binary")
        throw InputError(path, line, "DATA ascii or binary (binary_compressed is not supported)");
      std::size_t offset = 0;
      for (std::size_t k = 0; k < fields.size(); ++k) {
        if (fields[k].size != 1 && fields[k].size != 2 && fields[k].size != 4 &&
            fields[k].size != 8)
          throw InputError(path, line, "field sizes of 1, 2, 4 or 8 bytes");
        fields[k].offset = offset;
        offset += fields[k].size * (k < counts.size() ? std::max<std::size_t>(1, counts[k]) : 1);
      }
      if (points > limits::kMaxRecords) throw InputError(path, line, "at most 1e8 points");
      return read_body(path, bytes, at, points, fields, offset, w == "binary", line, stats);
    }
  }
  throw InputError(path, line, "a DATA line ending the PCD header");
}

Cloud read_ply(const std::string& path, const std::string& bytes, LidarReadStats& stats) {
  std::vector<Field> fields;
  std::size_t at = 0, line = 0, vertices = 0, offset = 0;
  bool binary = false, in_vertex = false, seen_vertex = false;
  while (at < bytes.size()) {
    const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
    std::istringstream words(bytes.substr(at, end - at));
    at = end + 1;
    ++line;
    std::string key, a, b;
    words >> key;
    if (line == 1 && key != "ply") throw InputError(path, 1, "'ply' on the first line");
    if (key == "format") {
      words >> a;
      if (a != "ascii" && a != "binary_little_endian")
        throw InputError(path, line, "format ascii or binary_little_endian");
      binary = a == "binary_little_endian";
    } else if (key == "element") {
      words >> a >> b;
      if (seen_vertex && !in_vertex) continue;
      in_vertex = a == "vertex";
      if (!in_vertex && !seen_vertex) throw InputError(path, line, "the vertex element first");
      seen_vertex = seen_vertex || in_vertex;
      if (in_vertex) vertices = std::strtoull(b.c_str(), nullptr, 10);
    } else if (key == "property" && in_vertex) {
      words >> a >> b;
      if (a == "list") throw InputError(path, line, "scalar vertex properties");
      static const std::pair<const char*, Field> kTypes[] = {
          {"float", {"", 0, 4, 'F'}},   {"float32", {"", 0, 4, 'F'}}, {"double", {"", 0, 8, 'F'}},
          {"float64", {"", 0, 8, 'F'}}, {"uchar", {"", 0, 1, 'U'}},   {"uint8", {"", 0, 1, 'U'}},
          {"ushort", {"", 0, 2, 'U'}},  {"uint16", {"", 0, 2, 'U'}},  {"uint", {"", 0, 4, 'U'}},
          {"uint32", {"", 0, 4, 'U'}},  {"char", {"", 0, 1, 'I'}},    {"int8", {"", 0, 1, 'I'}},
          {"short", {"", 0, 2, 'I'}},   {"int16", {"", 0, 2, 'I'}},   {"int", {"", 0, 4, 'I'}},
          {"int32", {"", 0, 4, 'I'}}};
      const auto* t = std::find_if(std::begin(kTypes), std::end(kTypes),
                                   [&](const auto& e) { return a == e.first; });
      if (t == std::end(kTypes)) throw InputError(path, line, "a PLY scalar type, found " + a);
      Field f = t->second;
      f.name = b;
      f.offset = offset;
      offset += f.size;
      fields.push_back(f);
    } else if (key == "end_header") {
      if (vertices > limits::kMaxRecords) throw InputError(path, line, "at most 1e8 vertices");
      return read_body(path, bytes, at, vertices, fields, offset, binary, line, stats);
    }
  }
  throw InputError(path, line, "an end_header line ending the PLY header");
}

using Reader = Cloud (*)(const std::string& path, const std::string& bytes, LidarReadStats&);

// The reader for a scan's file name (gzip-compressed or not), or nullptr.
Reader reader_for(std::string_view name) {
  if (ends_with(name, ".gz")) name.remove_suffix(3);
  if (ends_with(name, ".bin")) return read_bin;
  if (ends_with(name, ".pcd")) return read_pcd;
  if (ends_with(name, ".ply")) return read_ply;
  return nullptr;
}

constexpr const char* kScanNames = "*.bin, *.pcd or *.ply (each also .gz)";

}  // namespace

Cloud read_lidar_scan(const std::string& path, LidarReadStats* stats) {
  LidarReadStats local;
  LidarReadStats& s = stats ? *stats : local;
  s = {};
  const Reader read = reader_for(path);
  if (!read) throw InputError(path, 0, std::string("a LiDAR scan named ") + kScanNames);
  return read(path, file_bytes(path), s);
}

std::vector<std::string> lidar_scan_files(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  for (const std::string& p : paths) {
    if (!fs::exists(p)) throw InputError(p, 0, "an existing scan file or folder");
    if (!fs::is_directory(p)) {
      out.push_back(p);
      continue;
    }
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(p)) {
      const std::string f = e.path().string();
      if (e.is_regular_file() && reader_for(f)) found.push_back(f);
    }
    if (found.empty()) throw InputError(p, 0, std::string("a folder with ") + kScanNames);
    std::sort(found.begin(), found.end());
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

}  // namespace loopscan::io
