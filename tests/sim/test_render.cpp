// Stereo rendering of the synthetic world and the PNG files it writes.
#include <gtest/gtest.h>

#include "support/rendered_street.hpp"
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/png.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("loopscan_render_" + std::to_string(::getpid()) + name);
}

void u32(std::string& s, std::uint32_t v) {
  for (int k = 24; k >= 0; k -= 8) s.push_back(static_cast<char>((v >> k) & 0xff));
}

void chunk(std::string& out, const std::string& type, const std::string& data) {
  u32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  u32(out, static_cast<std::uint32_t>(crc32(0L, reinterpret_cast<const Bytef*>(body.data()),
                                            static_cast<uInt>(body.size()))));
}

// An independent encoder using row filter `filter` on every row (the reader must undo all 5).
std::string encode_png(int w, int h, const std::vector<std::uint8_t>& px, int filter,
                       int colour_type = 0) {
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw.push_back(static_cast<char>(filter));
    for (int x = 0; x < w; ++x) {
      const int a = x ? px[y * w + x - 1] : 0, b = y ? px[(y - 1) * w + x] : 0;
      const int c = (x && y) ? px[(y - 1) * w + x - 1] : 0;
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      const int pred[5] = {0, a, b, (a + b) / 2, (pa <= pb && pa <= pc) ? a : (pb <= pc ? b : c)};
      raw.push_back(static_cast<char>((px[y * w + x] - pred[filter]) & 0xff));
    }
  }
  uLongf n = compressBound(raw.size());
  std::string z(n, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &n, reinterpret_cast<const Bytef*>(raw.data()),
           raw.size());
  z.resize(n);
  std::string out("\x89PNG\r\n\x1a\n", 8), ihdr;
  u32(ihdr, w);
  u32(ihdr, h);
  ihdr += std::string{8, static_cast<char>(colour_type), 0, 0, 0};
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", z);
  chunk(out, "IEND", "");
  return out;
}

TEST(Png, RoundTripAndEveryRowFilter) {
  std::mt19937 rng(1);
  const int w = 37, h = 11;
  std::vector<std::uint8_t> px(w * h);
  for (auto& v : px) v = static_cast<std::uint8_t>(rng());
  const fs::path p = temp_file("a.png");
  io::write_png_gray(p.string(), w, h, px);
  const io::GrayPng back = io::read_png_gray(p.string());
  EXPECT_EQ(back.width, w);
  EXPECT_EQ(back.height, h);
  EXPECT_EQ(back.pixels, px);
  for (int filter = 0; filter < 5; ++filter) {
    std::ofstream(p, std::ios::binary) << encode_png(w, h, px, filter);
    EXPECT_EQ(io::read_png_gray(p.string()).pixels, px) << "filter " << filter;
  }
  fs::remove(p);
}

TEST(Png, DamagedOrUnsupportedFilesAreClearErrors) {
  const std::vector<std::uint8_t> px(20, 7);
  const fs::path p = temp_file("b.png");
  auto message = [&](const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
    try {
      io::read_png_gray(p.string());
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  std::string good = encode_png(5, 4, px, 0);
  std::string flipped = good;
  flipped[40] = static_cast<char>(flipped[40] ^ 1);
  EXPECT_NE(message(flipped).find("CRC"), std::string::npos) << message(flipped);
  EXPECT_NE(message(good.substr(0, good.size() - 20)).find("truncated"), std::string::npos);
  EXPECT_NE(message(encode_png(5, 4, px, 0, 2)).find("colour type 2"), std::string::npos);
  EXPECT_NE(message("GIF89a").find("PNG"), std::string::npos);
  fs::remove(p);
}

const test::ShortStreet& street() {
  static const test::ShortStreet s(0.25);
  return s;
}

TEST(Render, ScaledCameraKeepsTheGeometry) {
  const sim::StereoCamera full, half = sim::scaled_camera(full, 0.5);
  EXPECT_EQ(half.width, 621);
  EXPECT_EQ(half.height, 188);
  EXPECT_NEAR(half.baseline(), full.baseline(), 1e-12);
  // The same camera-frame point lands on the same place of the image.
  const Eigen::Vector3d p(1.3, -0.4, 12.0);
  Eigen::Vector2d a, b;
  ASSERT_TRUE(full.project(p, a));
  ASSERT_TRUE(half.project(p, b));
  EXPECT_NEAR((b.x() + 0.5) / half.width, (a.x() + 0.5) / full.width, 1e-3);
  EXPECT_NEAR((b.y() + 0.5) / half.height, (a.y() + 0.5) / full.height, 1e-3);
}

TEST(Render, DeterministicAndIndependentOfThreads) {
  const test::ShortStreet& s = street();
  sim::RenderConfig one, two;
  two.threads = 2;
  const auto& T = s.route.T_world_cam[30];
  const sim::GrayImage a = sim::render_view(s.world, s.conditions, s.camera, T, 0, 30, one);
  const sim::GrayImage b = sim::render_view(s.world, s.conditions, s.camera, T, 0, 30, two);
  EXPECT_EQ(a.pixels, b.pixels);
  const sim::GrayImage c = sim::render_view(s.world, s.conditions, s.camera, T, 0, 31, one);
  EXPECT_NE(a.pixels, c.pixels);  // another frame: other sensor noise
  // Textured enough for a VO: a good share of strong horizontal gradients.
  int strong = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 1; x < a.width; ++x) strong += std::abs(a.at(x, y) - a.at(x - 1, y)) > 12;
  }
  EXPECT_GT(strong, a.width * a.height / 50);
}

TEST(Render, RightImageIsTheLeftShiftedByTheDisparity) {
  // For pixels of the left image that see a surface at depth z, the right image shows the same
  // gray bf / z pixels to the left; a wrong disparity matches much worse.
  const test::ShortStreet& s = street();
  sim::RenderConfig rc;
  rc.noise_sigma = 0;
  const auto& T = s.route.T_world_cam[60];
  const sim::GrayImage L = sim::render_view(s.world, s.conditions, s.camera, T, 0, 60, rc);
  const sim::GrayImage R = sim::render_view(s.world, s.conditions, s.camera, T, 1, 60, rc);
  std::vector<double> right, wrong;
  for (int v = 0; v < L.height; v += 2) {
    for (int u = 0; u < L.width; u += 2) {
      const Eigen::Vector3d ray = s.camera.ray(u, v);
      const auto hit = s.world.raycast(T.translation(), T.linear() * ray, 150.0, s.conditions);
      if (!hit) continue;
      const double z = (T.inverse() * hit->point).z();
      const int d = static_cast<int>(std::lround(s.camera.bf / z));
      if (u - d - 3 < 0) continue;
      right.push_back(std::abs(L.at(u, v) - R.at(u - d, v)));
      wrong.push_back(std::abs(L.at(u, v) - R.at(u - d - 3, v)));
    }
  }
  ASSERT_GT(right.size(), 200u);
  auto mean = [](const std::vector<double>& x) {
    double sum = 0;
    for (double v : x) sum += v;
    return sum / x.size();
  };
  EXPECT_LT(mean(right), 0.5 * mean(wrong)) << mean(right) << " vs " << mean(wrong);
  EXPECT_LT(mean(right), 6.0);
}

}  // namespace
}  // namespace loopscan
