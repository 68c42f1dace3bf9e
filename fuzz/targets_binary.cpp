// The binary readers: place databases (Scan Context and DELIGHT), vocabularies, images (PNG
// through loopscan's decoder, JPEG through OpenCV after the header check).
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "fuzz_target.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/core/database/database.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/png.hpp"
#include "loopscan/io/vocabulary_file.hpp"
#include "loopscan/vo/image_file.hpp"
#include "seed_inputs.hpp"

namespace loopscan::fuzz {
namespace {

std::string database_bytes(Method method, int places) {
  DatabaseConfig cfg;
  cfg.method = method;
  Database db(cfg);
  for (int i = 0; i < places; ++i) {
    Signature s = Signature::Zero(rows_per_place(method), signature_columns(method));
    for (Eigen::Index k = 0; k < s.size(); k += 7)
      s(k) = method == Method::Delight ? k % 5 : 0.01 * (k % 13);
    PlaceDescriptor d{s};
    std::optional<Pose3x4> pose;
    if (i % 2 == 0) pose = Pose3x4::Identity();
    db.add({i % 2, 30 + i}, d, pose);
  }
  return bytes_written_by([&](const std::string& p) { io::save_database(db, p); });
}

std::string vocabulary_bytes() {
  const io::VocabularyData v = small_vocabulary(2);
  return bytes_written_by([&](const std::string& p) { io::save_vocabulary(p, v); });
}

Target binary(const std::string& name, const std::string& file, std::vector<std::string> seeds,
              std::function<void(const std::string&)> read_file) {
  return single_file(name, file, Format::Binary, std::move(seeds), std::move(read_file));
}

}  // namespace

std::vector<Target> binary_targets() {
  std::vector<Target> t;
  Target db = binary("database", "map.db",
                     {database_bytes(Method::ScanContext, 3), database_bytes(Method::Delight, 2),
                      database_bytes(Method::M2dp, 2)},
                     [](const std::string& p) { io::load_database(p); });
  db.trailing_crc = true;
  t.push_back(db);
  Target voc = binary("vocabulary", "voc.bin", {vocabulary_bytes()},
                      [](const std::string& p) { baselines::read_vocabulary(p); });
  voc.trailing_crc = true;
  t.push_back(voc);
  Target png = binary(
      "png", "image.png",
      {image_bytes(".png", CV_8UC1), image_bytes(".png", CV_16UC3), image_bytes(".png", CV_8UC4)},
      [](const std::string& p) { vo::read_gray_image(p); });
  png.png_chunks = true;
  t.push_back(png);
  Target jpeg =
      binary("jpeg", "image.jpg", {image_bytes(".jpg", CV_8UC1), image_bytes(".jpg", CV_8UC3)},
             [](const std::string& p) { vo::read_gray_image(p); });
  jpeg.noisy_stderr = true;
  t.push_back(jpeg);
  return t;
}

}  // namespace loopscan::fuzz
