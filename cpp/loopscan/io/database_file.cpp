#include "loopscan/io/database_file.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/binary_stream.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"

namespace loopscan::io {
namespace {

constexpr char kMagic[8] = {'L', 'O', 'O', 'P', 'S', 'C', 'D', 'B'};
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 4 + 8 + 4 + 4 + 4 + 4 + 8;
// Version 5: the bird's-eye layout (cell kind, cell_m, range_m, rings, angles); version 6 adds
// its weight window (taper_start_m, taper_end_m).
constexpr std::size_t kBirdsEyeLayoutBytes = 1 + 8 + 8 + 4 + 4;
constexpr std::size_t kBirdsEyeWindowBytes = 8 + 8;
constexpr std::size_t kPlaceFixedBytes = 4 + 4 + 1 + 9 * 4;
constexpr std::size_t kPoseBytes = 12 * 8;
constexpr std::size_t kMaxCloudPoints = std::size_t(1) << 20;
constexpr float kMaxCloudM = 327.67f;   // int16 centimetres
constexpr std::uint8_t kUnknown = 255;  // mode or frame of a map saved before version 4

std::string describe(const DatabaseConfig& c) {
  return method_name(c.method) + "/" + fusion_name(c.fusion) + " w_s " +
         std::to_string(c.structure_weight) + ", " + std::to_string(c.scan_context.rings) + "x" +
         std::to_string(c.scan_context.sectors) + ", " + std::to_string(c.columns) + " columns" +
         (c.method == Method::BirdsEye
              ? ", bird's-eye " + birds_eye_cell_name(c.birds_eye.cell) + " cells of " +
                    std::to_string(c.birds_eye.cell_m) + " m to " +
                    std::to_string(c.birds_eye.range_m) + " m weighed from " +
                    std::to_string(c.birds_eye.taper_start_m) + " to " +
                    std::to_string(c.birds_eye.taper_end_m) + " m, key " +
                    std::to_string(c.birds_eye.rings) + "x" + std::to_string(c.birds_eye.angles)
              : "");
}

bool same_parameters(const DatabaseConfig& a, const DatabaseConfig& b) {
  const int ca = a.columns > 0 ? a.columns : signature_columns(a.method);
  const int cb = b.columns > 0 ? b.columns : signature_columns(b.method);
  const bool sc = a.method == Method::ScanContext;
  return a.method == b.method && a.fusion == b.fusion && a.structure_weight == b.structure_weight &&
         (!sc || (a.scan_context.rings == b.scan_context.rings &&
                  a.scan_context.sectors == b.scan_context.sectors)) &&
         (sc || ca == cb) &&
         (a.method != Method::BirdsEye || same_layout(a.birds_eye, b.birds_eye));
}

// What a place record must hold beyond its bytes: ids >= 0, a rotation as the descriptor
// frame (PCA axes), a finite pose within the coordinate bound.
void check_place(const Reader& r, std::uint64_t i, const PlaceRef& p,
                 const Eigen::Matrix<float, 3, 3, Eigen::RowMajor>& frame,
                 const std::optional<Pose3x4>& pose) {
  const std::string place = "place " + std::to_string(i) + ": ";
  if (p.session < 0 || p.keyframe < 0) {
    r.fail(place + "session " + std::to_string(p.session) + ", keyframe " +
           std::to_string(p.keyframe) + ", expected both >= 0");
  }
  const Eigen::Matrix3d f = frame.cast<double>();
  if (!f.allFinite() ||
      !((f * f.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-3)) {
    r.fail(place + "the descriptor frame is not a rotation matrix");
  }
  if (pose && !(pose->cwiseAbs().maxCoeff() <= limits::kMaxCoordinateM)) {
    r.fail(place + "the pose has NaN, infinite or values beyond +-1e9");
  }
}

// The cloud section: every count checked against the bytes left before reading them.
void read_clouds(Reader& r, std::uint64_t count, std::uintmax_t file_size,
                 std::vector<PlaceCloud>* clouds) {
  const auto present = r.get<std::uint8_t>("the cloud flag");
  if (present > 1) r.fail("cloud flag " + std::to_string(present) + ", expected 0 or 1");
  if (!present) return;
  std::vector<std::int16_t> xyz;
  for (std::uint64_t i = 0; i < count; ++i) {
    const auto n = r.get<std::uint32_t>("a cloud's point count");
    const auto structure = r.get<std::uint32_t>("a cloud's structure count");
    if (n > kMaxCloudPoints || structure > n) {
      r.fail("cloud " + std::to_string(i) + ": " + std::to_string(n) + " points, " +
             std::to_string(structure) +
             " structure points, expected at most 2^20 and "
             "structure <= points");
    }
    if (r.offset() + 6ull * n + 4 > file_size) {
      r.fail("cloud " + std::to_string(i) + ": the file is too short for " + std::to_string(n) +
             " points (truncated?)");
    }
    xyz.resize(3 * std::size_t(n));
    r.bytes(xyz.data(), xyz.size() * sizeof(std::int16_t), "cloud points");
    if (!clouds) continue;
    PlaceCloud c;
    c.structure = structure;
    c.points.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      c.points.emplace_back(xyz[3 * k] * 0.01f, xyz[3 * k + 1] * 0.01f, xyz[3 * k + 2] * 0.01f);
    }
    clouds->push_back(std::move(c));
  }
}

}  // namespace

void save_database(const Database& db, const std::string& path,
                   const std::vector<PlaceCloud>* clouds) {
  if (clouds && clouds->size() != db.size()) {
    throw std::invalid_argument("save_database: " + std::to_string(clouds->size()) +
                                " clouds for " + std::to_string(db.size()) + " places");
  }
  if (clouds) {
    for (const PlaceCloud& c : *clouds) {
      if (c.structure > c.points.size() || c.points.size() > kMaxCloudPoints) {
        throw std::invalid_argument(
            "save_database: a cloud of more than 2^20 points or with "
            "more structure points than points");
      }
      for (const Eigen::Vector3f& p : c.points) {
        if (!(p.cwiseAbs().maxCoeff() < kMaxCloudM)) {
          throw std::invalid_argument(
              "save_database: a cloud point beyond 327 m of its keyframe (or NaN)");
        }
      }
    }
  }
  AtomicWriter file(path);
  Writer w(file.stream());
  const DatabaseConfig& c = db.config();
  w.bytes(kMagic, sizeof kMagic);
  w.put<std::uint32_t>(kDatabaseFileVersion);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(c.method));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(c.fusion));
  w.put<double>(c.structure_weight);
  w.put<std::int32_t>(c.scan_context.rings);
  w.put<std::int32_t>(c.scan_context.sectors);
  w.put<std::int32_t>(c.columns > 0 ? c.columns : signature_columns(c.method));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(c.storage));
  w.put<std::uint8_t>(c.mode ? static_cast<std::uint8_t>(*c.mode) : kUnknown);
  w.put<std::uint8_t>(c.frame ? static_cast<std::uint8_t>(*c.frame) : kUnknown);
  w.put<std::uint8_t>(static_cast<std::uint8_t>(c.birds_eye.cell));
  w.put<double>(c.birds_eye.cell_m);
  w.put<double>(c.birds_eye.range_m);
  w.put<std::int32_t>(c.birds_eye.rings);
  w.put<std::int32_t>(c.birds_eye.angles);
  w.put<double>(c.birds_eye.taper_start_m);
  w.put<double>(c.birds_eye.taper_end_m);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(db.payload_floats()));
  w.put<std::uint64_t>(db.size());
  std::vector<float> payload(static_cast<std::size_t>(db.payload_floats()));
  for (std::size_t i = 0; i < db.size(); ++i) {
    const PlaceRef p = db.place(i);
    w.put<std::int32_t>(p.session);
    w.put<std::int32_t>(p.keyframe);
    const std::optional<Pose3x4> pose = db.pose(i);
    w.put<std::uint8_t>(pose ? 1 : 0);
    const Eigen::Matrix<float, 3, 3, Eigen::RowMajor> frame = db.frame(i);
    w.bytes(frame.data(), 9 * sizeof(float));
    if (pose) {
      const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> T = *pose;
      w.bytes(T.data(), 12 * sizeof(double));
    }
    db.stored_payload(i, payload.data());
    w.bytes(payload.data(), payload.size() * sizeof(float));
  }
  w.put<std::uint8_t>(clouds ? 1 : 0);
  if (clouds) {
    std::vector<std::int16_t> xyz;
    for (const PlaceCloud& cloud : *clouds) {
      w.put<std::uint32_t>(static_cast<std::uint32_t>(cloud.points.size()));
      w.put<std::uint32_t>(static_cast<std::uint32_t>(cloud.structure));
      xyz.clear();
      for (const Eigen::Vector3f& p : cloud.points) {
        for (int k = 0; k < 3; ++k)
          xyz.push_back(static_cast<std::int16_t>(std::lround(p[k] * 100.0f)));
      }
      w.bytes(xyz.data(), xyz.size() * sizeof(std::int16_t));
    }
  }
  const std::uint32_t crc = w.crc();
  file.stream().write(reinterpret_cast<const char*>(&crc), sizeof crc);
  file.commit();
}

Database load_database(const std::string& path, const DatabaseConfig* expected,
                       std::vector<PlaceCloud>* clouds) {
  if (clouds) clouds->clear();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "a readable place database file");
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, 0, "a place database file whose size can be read");
  Reader r(in, path);

  char magic[8];
  r.bytes(magic, sizeof magic, "the magic \"LOOPSCDB\"");
  if (std::memcmp(magic, kMagic, sizeof magic) != 0) {
    r.fail("not a loopscan place database (expected the magic \"LOOPSCDB\")");
  }
  const auto version = r.get<std::uint32_t>("the format version");
  if (version < 1 || version > kDatabaseFileVersion) {
    r.fail("format version " + std::to_string(version) + ", this build reads versions 1 to " +
           std::to_string(kDatabaseFileVersion));
  }
  DatabaseConfig c;
  const auto method = r.get<std::uint32_t>("the descriptor kind");
  constexpr auto kLastMethod = static_cast<std::uint32_t>(Method::BirdsEye);
  if (method > kLastMethod) {
    r.fail("descriptor kind " + std::to_string(method) + ", expected 0.." +
           std::to_string(kLastMethod));
  }
  c.method = static_cast<Method>(method);
  const auto fusion = r.get<std::uint32_t>("the fusion");
  if (fusion > 2) r.fail("fusion " + std::to_string(fusion) + ", expected 0..2");
  c.fusion = static_cast<Fusion>(fusion);
  c.structure_weight = r.get<double>("the structure weight");
  if (!(c.structure_weight >= 0 && c.structure_weight <= 1000)) {
    r.fail("structure weight " + std::to_string(c.structure_weight) +
           ", expected a finite number in [0, 1000]");
  }
  c.scan_context.rings = r.get<std::int32_t>("the ring count");
  c.scan_context.sectors = r.get<std::int32_t>("the sector count");
  c.columns = r.get<std::int32_t>("the signature width");
  const bool sc = c.method == Method::ScanContext;
  if (sc &&
      (c.scan_context.rings <= 0 || c.scan_context.rings > 4096 || c.scan_context.sectors <= 0 ||
       c.scan_context.sectors > 512 || c.scan_context.sectors % 2 != 0)) {
    r.fail("Scan Context size " + std::to_string(c.scan_context.rings) + " x " +
           std::to_string(c.scan_context.sectors) +
           ", expected rings in 1..4096 and an even "
           "sector count in 2..512");
  }
  if (c.columns <= 0 || c.columns > (1 << 20)) {
    r.fail("signature width " + std::to_string(c.columns) + ", expected 1..1048576");
  }
  if (version >= 3) {
    const auto storage = r.get<std::uint32_t>("the place storage");
    if (storage > 1) r.fail("place storage " + std::to_string(storage) + ", expected 0 or 1");
    c.storage = static_cast<PlaceStorage>(storage);
  }
  if (version >= 4) {
    const auto mode = r.get<std::uint8_t>("the mode");
    if (mode > 1 && mode != kUnknown)
      r.fail("mode " + std::to_string(mode) + ", expected 0 (reference), 1 (default) or 255");
    if (mode != kUnknown) c.mode = static_cast<Mode>(mode);
    const auto frame = r.get<std::uint8_t>("the descriptor frame kind");
    if (frame > 3 && frame != kUnknown)
      r.fail("descriptor frame kind " + std::to_string(frame) + ", expected 0..3 or 255");
    if (frame != kUnknown) c.frame = static_cast<DescriptorFrame>(frame);
  }
  if (version >= 5) {  // earlier files hold the default layout
    const auto cell = r.get<std::uint8_t>("the bird's-eye cell kind");
    if (cell > 1) r.fail("bird's-eye cell kind " + std::to_string(cell) + ", expected 0 or 1");
    c.birds_eye.cell = static_cast<BirdsEyeCell>(cell);
    c.birds_eye.cell_m = r.get<double>("the bird's-eye cell size");
    c.birds_eye.range_m = r.get<double>("the bird's-eye range");
    c.birds_eye.rings = r.get<std::int32_t>("the bird's-eye key rings");
    c.birds_eye.angles = r.get<std::int32_t>("the bird's-eye key angles");
  }
  if (version >= 6) {
    c.birds_eye.taper_start_m = r.get<double>("the bird's-eye weights' start");
    c.birds_eye.taper_end_m = r.get<double>("the bird's-eye weights' end");
  } else if (version == 5) {  // the window version 5's places were described with
    c.birds_eye.taper_start_m = 10.0;
    c.birds_eye.taper_end_m = 30.0;
  }
  try {  // whatever the method: no impossible layout is loaded
    validate(c.birds_eye);
  } catch (const std::invalid_argument& e) {
    r.fail(e.what());
  }
  if (expected && !same_parameters(c, *expected)) {
    r.fail("built with " + describe(c) + ", expected " + describe(*expected));
  }
  Database db = [&] {
    try {
      return Database(c);
    } catch (const std::invalid_argument& e) {
      r.fail(std::string("parameters rejected: ") + e.what());
    }
  }();
  const auto floats = r.get<std::uint32_t>("the payload size");
  if (floats != static_cast<std::uint32_t>(db.payload_floats())) {
    r.fail("payload of " + std::to_string(floats) + " floats, these parameters give " +
           std::to_string(db.payload_floats()));
  }
  const auto count = r.get<std::uint64_t>("the place count");
  // The size must fit the count before anything is allocated for it.
  const std::uintmax_t record = kPlaceFixedBytes + std::uintmax_t(floats) * 4;
  const std::size_t header = kHeaderBytes + (version >= 3 ? 4 : 0) + (version >= 4 ? 2 : 0) +
                             (version >= 5 ? kBirdsEyeLayoutBytes : 0) +
                             (version >= 6 ? kBirdsEyeWindowBytes : 0);
  const std::uintmax_t body = file_size - header;
  if (file_size < header + 4 || count > (body - 4) / record) {
    r.fail("the file is too short for " + std::to_string(count) + " places (truncated?)");
  }

  std::vector<float> payload(floats);
  for (std::uint64_t i = 0; i < count; ++i) {
    PlaceRef p;
    p.session = r.get<std::int32_t>("a session");
    p.keyframe = r.get<std::int32_t>("a keyframe id");
    const auto has_pose = r.get<std::uint8_t>("a pose flag");
    if (has_pose > 1) r.fail("pose flag " + std::to_string(has_pose) + ", expected 0 or 1");
    Eigen::Matrix<float, 3, 3, Eigen::RowMajor> frame;
    r.bytes(frame.data(), 9 * sizeof(float), "a descriptor frame");
    std::optional<Pose3x4> pose;
    if (has_pose) {
      Eigen::Matrix<double, 3, 4, Eigen::RowMajor> T;
      r.bytes(T.data(), 12 * sizeof(double), "a pose");
      pose = T;
    }
    r.bytes(payload.data(), payload.size() * sizeof(float), "a place payload");
    check_place(r, i, p, frame, pose);
    try {
      db.add_stored(p, payload.data(), frame, pose);  // checks the payload's values
    } catch (const std::invalid_argument& e) {
      r.fail("place " + std::to_string(i) + ": " + e.what());
    }
  }
  if (version >= 2) read_clouds(r, count, file_size, clouds);
  const std::uint32_t crc = r.crc();
  std::uint32_t stored = 0;
  if (!in.read(reinterpret_cast<char*>(&stored), sizeof stored)) {
    r.fail("unexpected end of file, expected the checksum");
  }
  if (stored != crc) r.fail("checksum mismatch: the file is corrupted");
  if (in.peek() != std::char_traits<char>::eof()) r.fail("unexpected data after the checksum");
  return db;
}

}  // namespace loopscan::io
