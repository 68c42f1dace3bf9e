// Persistence of the place database: bit-exact round trip, and a fuzz of truncations and bit
// flips that must all be rejected with io::InputError (never a crash, never a silent load).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include <zlib.h>
#include "loopscan/core/database/database.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

Signature random_place(Method m, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Signature s = Signature::Zero(rows_per_place(m), signature_columns(m));
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (u(rng) < 0.3) s(i) = m == Method::Delight ? std::floor(9 * u(rng)) : u(rng);
  }
  return s;
}

Database sample_database(Method m, int n) {
  std::mt19937 rng(11);
  DatabaseConfig cfg;
  cfg.method = m;
  Database db(cfg);
  for (int i = 0; i < n; ++i) {
    PlaceDescriptor d{random_place(m, rng)};
    d.frame = Eigen::Matrix3d::Identity() * (i % 2 ? -1.0 : 1.0);
    std::optional<Pose3x4> pose;
    if (i % 3 == 0) pose = Pose3x4::Random();
    db.add({i % 2, 100 + i}, d, pose);
  }
  return db;
}

class DatabaseFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("loopscan_dbfile_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(DatabaseFile, RoundTripIsBitExactForEveryMethod) {
  for (Method m : {Method::ScanContext, Method::M2dp, Method::Delight}) {
    const Database db = sample_database(m, 12);
    io::save_database(db, path("a.db"));
    const Database back = io::load_database(path("a.db"));
    ASSERT_EQ(back.size(), db.size());
    io::save_database(back, path("b.db"));
    EXPECT_EQ(read_bytes(path("a.db")), read_bytes(path("b.db"))) << method_name(m);
    for (std::size_t i = 0; i < db.size(); ++i) {
      EXPECT_EQ(back.place(i), db.place(i));
      EXPECT_EQ(back.pose(i).has_value(), db.pose(i).has_value());
      if (db.pose(i)) {
        EXPECT_EQ(*back.pose(i), *db.pose(i));
      }
      EXPECT_EQ(back.frame(i), db.frame(i));
    }
    // Same answers from the loaded database.
    std::mt19937 rng(3);
    const PlaceDescriptor q{random_place(m, rng)};
    const auto a = db.query(q, 3), b = back.query(q, 3);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t j = 0; j < a.size(); ++j) {
      EXPECT_EQ(a[j].index, b[j].index);
      EXPECT_EQ(a[j].distance, b[j].distance);
    }
    EXPECT_FALSE(fs::exists(path("a.db") + ".tmp." + std::to_string(::getpid())));
  }
}

// A map records how its places were described (file version 4), so that queries and later
// sessions can be checked against it; a map that does not know says so (nullopt).
TEST_F(DatabaseFile, ModeAndDescriptorFrameRoundTrip) {
  for (Mode mode : {Mode::Reference, Mode::Default}) {
    for (DescriptorFrame frame : {DescriptorFrame::Pca, DescriptorFrame::Camera,
                                  DescriptorFrame::GravityPca, DescriptorFrame::Centroid}) {
      DatabaseConfig cfg;
      cfg.method = Method::M2dp;
      cfg.mode = mode;
      cfg.frame = frame;
      io::save_database(Database(cfg), path("m.db"));
      const Database back = io::load_database(path("m.db"));
      ASSERT_TRUE(back.config().mode && back.config().frame);
      EXPECT_EQ(*back.config().mode, mode);
      EXPECT_EQ(*back.config().frame, frame);
    }
  }
  io::save_database(Database{}, path("u.db"));
  const Database unknown = io::load_database(path("u.db"));
  EXPECT_FALSE(unknown.config().mode.has_value());
  EXPECT_FALSE(unknown.config().frame.has_value());
}

TEST_F(DatabaseFile, EmptyDatabaseRoundTrips) {
  io::save_database(Database{}, path("e.db"));
  EXPECT_EQ(io::load_database(path("e.db")).size(), 0u);
}

TEST_F(DatabaseFile, FuzzedFilesAreRejectedNeverLoaded) {
  const Database db = sample_database(Method::ScanContext, 6);
  io::save_database(db, path("good.db"));
  const std::string good = read_bytes(path("good.db"));
  std::mt19937 rng(2024);
  int rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string bad = good;
    if (trial % 3 == 0) {
      bad.resize(std::uniform_int_distribution<std::size_t>(0, good.size() - 1)(rng));
    } else {
      const int flips = 1 + trial % 4;
      for (int f = 0; f < flips; ++f) {
        const std::size_t byte = std::uniform_int_distribution<std::size_t>(0, bad.size() - 1)(rng);
        bad[byte] = static_cast<char>(bad[byte] ^ (1 << (rng() % 8)));
      }
    }
    write_bytes(path("bad.db"), bad);
    try {
      io::load_database(path("bad.db"));
      ADD_FAILURE() << "trial " << trial << " loaded a damaged file";
    } catch (const io::InputError& e) {
      ++rejected;
      EXPECT_NE(std::string(e.what()).find("bad.db"), std::string::npos);
    }
  }
  EXPECT_EQ(rejected, 300);
  write_bytes(path("bad.db"), good + "x");
  EXPECT_THROW(io::load_database(path("bad.db")), io::InputError);
}

TEST_F(DatabaseFile, WrongVersionMagicAndParametersHaveClearErrors) {
  io::save_database(sample_database(Method::ScanContext, 2), path("g.db"));
  const std::string good = read_bytes(path("g.db"));
  auto message_of = [&](const std::string& file, const DatabaseConfig* expected = nullptr) {
    try {
      io::load_database(file, expected);
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  auto message = [&](const std::string& bytes, const DatabaseConfig* expected = nullptr) {
    write_bytes(path("x.db"), bytes);
    return message_of(path("x.db"), expected);
  };
  std::string v7 = good;
  v7[8] = 7;
  EXPECT_NE(message(v7).find("format version 7, this build reads versions 1 to 6"),
            std::string::npos)
      << message(v7);
  std::string storage = good;
  storage[40] = 7;  // the storage field after the header's columns
  EXPECT_NE(message(storage).find("place storage 7"), std::string::npos) << message(storage);
  EXPECT_NE(message("PK\x03\x04 not a database").find("LOOPSCDB"), std::string::npos);
  DatabaseConfig m2dp;
  m2dp.method = Method::M2dp;
  EXPECT_NE(message(good, &m2dp).find("expected m2dp"), std::string::npos) << message(good, &m2dp);
  DatabaseConfig same;
  EXPECT_EQ(message(good, &same), "loaded");
  const std::string missing = message_of(path("missing.db"));
  EXPECT_NE(missing.find("missing.db: expected a readable place database file"), std::string::npos)
      << missing;
}

// The spectral key is stored as uint16 pairs inside the payload's floats: a ring whose
// normalised DC term is large (one ring holding all of a half, equal in every sector) gives key
// bits that read as a float beyond 1e30 or as NaN. Such places are valid and must add, save
// and load (only the float part of a payload is checked for finite values).
TEST_F(DatabaseFile, ScanContextPlacesWithLargeSpectralKeysRoundTrip) {
  Database db;
  Signature s = Signature::Zero(1, 2400);
  for (int sector = 0; sector < 60; ++sector) {
    s(0, sector * 20 + 1) = 3.0;         // structure: ring 1 only, DC = sqrt(60) after norming
    s(0, 1200 + sector * 20 + 1) = 1.0;  // intensity likewise
  }
  ASSERT_NO_THROW(db.add({0, 1}, {s}));
  std::vector<float> payload(static_cast<std::size_t>(db.payload_floats()));
  db.stored_payload(0, payload.data());
  bool key_reads_as_huge = false;
  for (std::size_t i = 2400; i < payload.size(); ++i)
    key_reads_as_huge |= !(std::abs(payload[i]) <= 1e30f);
  EXPECT_TRUE(key_reads_as_huge) << "the case no longer exercises the packed key";
  io::save_database(db, path("k.db"));
  const Database back = io::load_database(path("k.db"));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back.query({s}, 1).front().place, (PlaceRef{0, 1}));
}

TEST_F(DatabaseFile, PlaceCloudsRoundTripToTheCentimetreAndVersion1StillLoads) {
  const Database db = sample_database(Method::ScanContext, 3);
  std::vector<PlaceCloud> clouds(3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-90.f, 90.f);
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    for (std::size_t k = 0; k < 50 * i; ++k)
      clouds[i].points.emplace_back(u(rng), u(rng) / 20, u(rng));
    clouds[i].structure = clouds[i].points.size() / 2;
  }
  io::save_database(db, path("c.db"), &clouds);
  std::vector<PlaceCloud> back;
  EXPECT_EQ(io::load_database(path("c.db"), nullptr, &back).size(), 3u);
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_EQ(back[i].points.size(), clouds[i].points.size());
    EXPECT_EQ(back[i].structure, clouds[i].structure);
    for (std::size_t k = 0; k < back[i].points.size(); ++k) {
      EXPECT_LE((back[i].points[k] - clouds[i].points[k]).cwiseAbs().maxCoeff(), 0.0051f);
    }
  }
  io::save_database(db, path("d.db"), &back);  // a loaded set saves to the same bytes
  EXPECT_EQ(read_bytes(path("c.db")), read_bytes(path("d.db")));
  // A file without clouds gives none; a version-1 file (no cloud section, no storage field)
  // loads.
  io::save_database(db, path("n.db"));
  EXPECT_EQ(io::load_database(path("n.db"), nullptr, &back).size(), 3u);
  EXPECT_TRUE(back.empty());
  std::string v1 = read_bytes(path("n.db"));
  v1[8] = 1;
  v1.erase(v1.size() - 5, 1);  // the cloud flag before the checksum
  // The storage field (version 3), mode and frame (version 4), bird's-eye layout (version 5)
  // and its weight window (version 6).
  v1.erase(40, 6 + 25 + 16);
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(v1.data()), static_cast<uInt>(v1.size() - 4)));
  std::memcpy(&v1[v1.size() - 4], &crc, 4);
  write_bytes(path("v1.db"), v1);
  EXPECT_EQ(io::load_database(path("v1.db")).size(), 3u);
  // Clouds that cannot be stored are refused before anything is written.
  clouds[1].points[0].x() = 400.f;
  EXPECT_THROW(io::save_database(db, path("bad.db"), &clouds), std::invalid_argument);
  clouds.pop_back();
  EXPECT_THROW(io::save_database(db, path("bad.db"), &clouds), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("bad.db")));
}

// Compact Scan Context places save and load as they are (no re-quantisation), answer as
// before, and say so in the file; the loader rebuilds the compact store.
TEST_F(DatabaseFile, CompactPlacesRoundTripByteForByte) {
  std::mt19937 rng(3);
  DatabaseConfig cfg;
  cfg.storage = PlaceStorage::Compact;
  Database db(cfg);
  std::vector<Signature> places;
  for (int i = 0; i < 40; ++i) {
    places.push_back(random_place(Method::ScanContext, rng));
    db.add({0, i}, {places.back()});
  }
  io::save_database(db, path("compact.db"));
  const Database back = io::load_database(path("compact.db"));
  EXPECT_EQ(back.config().storage, PlaceStorage::Compact);
  EXPECT_EQ(back.payload_floats(), db.payload_floats());
  io::save_database(back, path("compact2.db"));
  EXPECT_EQ(read_bytes(path("compact.db")), read_bytes(path("compact2.db")));
  QueryOptions exact;
  exact.retrieval = Retrieval::Exact;
  for (int i = 0; i < 40; i += 7) {
    const auto a = db.query({places[i]}, 3, exact), b = back.query({places[i]}, 3, exact);
    ASSERT_EQ(a.size(), 3u);
    ASSERT_EQ(b.size(), 3u);
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(a[j].index, b[j].index);
      EXPECT_EQ(a[j].distance, b[j].distance);
    }
    EXPECT_EQ(a[0].index, static_cast<std::size_t>(i));
  }
  // The full file of the same places is ~3.4x larger.
  Database full;
  for (int i = 0; i < 40; ++i) full.add({0, i}, {places[i]});
  io::save_database(full, path("full.db"));
  EXPECT_GT(fs::file_size(path("full.db")), 3 * fs::file_size(path("compact.db")));
}

}  // namespace
}  // namespace loopscan
