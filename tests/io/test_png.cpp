// The PNG codec: the writer round-trips, the reader undoes every row filter at every pixel
// size, converts every colour type and depth to gray, and rejects damaged or oversized files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/png.hpp"
#include "support/png_encoder.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("loopscan_png_" + std::to_string(::getpid()) + name);
}

io::GrayPng decode(const std::string& bytes) {
  const fs::path p = temp_file("d.png");
  std::ofstream(p, std::ios::binary) << bytes;
  io::GrayPng g = io::read_png_gray(p.string());
  fs::remove(p);
  return g;
}

std::vector<std::uint8_t> random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> v(n);
  for (auto& b : v) b = static_cast<std::uint8_t>(rng());
  return v;
}

TEST(Png, RoundTripAndEveryRowFilter) {
  const int w = 37, h = 11;
  const std::vector<std::uint8_t> px = random_bytes(w * h, 1);
  const fs::path p = temp_file("a.png");
  io::write_png_gray(p.string(), w, h, px);
  const io::GrayPng back = io::read_png_gray(p.string());
  EXPECT_EQ(back.width, w);
  EXPECT_EQ(back.height, h);
  EXPECT_EQ(back.pixels, px);
  fs::remove(p);
  for (int filter = 0; filter < 5; ++filter) {
    test::PngSpec s{w, h, 0, 8, filter, 0, px, ""};
    EXPECT_EQ(decode(test::encode_png(s)).pixels, px) << "filter " << filter;
  }
}

// Gray stored as RGB / RGBA / gray+alpha at 8 and 16 bits: every filter (the filters reach back
// one whole pixel, 2..8 bytes) must give the gray back exactly, as the weights sum to one and
// 16-bit samples keep their high byte.
TEST(Png, EveryColourTypeAndDepthGivesTheGrayBack) {
  const int w = 13, h = 6;
  const std::vector<std::uint8_t> gray = random_bytes(w * h, 2);
  const std::vector<std::uint8_t> noise = random_bytes(w * h * 8, 3);
  for (int colour : {0, 2, 4, 6}) {
    for (int depth : {8, 16}) {
      test::PngSpec s{w, h, colour, depth, 0, 0, {}, ""};
      const int bytes_per_sample = depth / 8;
      for (int i = 0; i < w * h; ++i) {
        for (int c = 0; c < s.channels(); ++c) {
          const bool alpha = (colour == 4 && c == 1) || (colour == 6 && c == 3);
          s.rows.push_back(alpha ? noise[i] : gray[i]);  // high byte (or the 8-bit sample)
          if (bytes_per_sample == 2) s.rows.push_back(noise[8 * i + c]);  // low byte: dropped
        }
      }
      for (int filter = 0; filter < 5; ++filter) {
        s.filter = filter;
        EXPECT_EQ(decode(test::encode_png(s)).pixels, gray)
            << "colour " << colour << " depth " << depth << " filter " << filter;
      }
    }
  }
}

TEST(Png, ColourWeightsPalettesAndLowBitDepths) {
  // Pure red, green and blue: OpenCV's libpng weights 9797, 19234, 3737 (/ 32768, truncated).
  test::PngSpec rgb{3, 1, 2, 8, 0, 0, {255, 0, 0, 0, 255, 0, 0, 0, 255}, ""};
  EXPECT_EQ(decode(test::encode_png(rgb)).pixels, (std::vector<std::uint8_t>{76, 149, 29}));
  // A 2-bit palette image: indices 0..3 through the palette's colours.
  test::PngSpec pal{
      4, 1, 3,      2,
      0, 0, {0x1B}, std::string("\x00\x00\x00\xff\xff\xff\x80\x80\x80\xff\x00\x00", 12)};
  EXPECT_EQ(decode(test::encode_png(pal)).pixels, (std::vector<std::uint8_t>{0, 255, 128, 76}));
  // 1, 2 and 4-bit gray scale to 0..255; rows are padded to whole bytes.
  test::PngSpec g1{10, 1, 0, 1, 0, 0, {0xA5, 0xC0}, ""};
  EXPECT_EQ(decode(test::encode_png(g1)).pixels,
            (std::vector<std::uint8_t>{255, 0, 255, 0, 0, 255, 0, 255, 255, 255}));
  test::PngSpec g2{3, 1, 0, 2, 0, 0, {0x1B}, ""};
  EXPECT_EQ(decode(test::encode_png(g2)).pixels, (std::vector<std::uint8_t>{0, 85, 170}));
  test::PngSpec g4{2, 1, 0, 4, 0, 0, {0x0F}, ""};
  EXPECT_EQ(decode(test::encode_png(g4)).pixels, (std::vector<std::uint8_t>{0, 255}));
}

std::string error_of(const std::string& bytes) {
  try {
    decode(bytes);
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "loaded";
}

TEST(Png, DamagedUnsupportedOrOversizedFilesAreClearErrors) {
  const std::vector<std::uint8_t> px(200, 7);
  const std::string good = test::encode_png({5, 4, 0, 8, 0, 0, px, ""});
  std::string flipped = good;
  flipped[40] = static_cast<char>(flipped[40] ^ 1);
  EXPECT_NE(error_of(flipped).find("CRC"), std::string::npos) << error_of(flipped);
  EXPECT_NE(error_of(good.substr(0, good.size() - 20)).find("truncated"), std::string::npos);
  EXPECT_NE(error_of(test::encode_png({5, 4, 5, 8, 0, 0, px, ""})).find("colour type 5"),
            std::string::npos);
  EXPECT_NE(error_of(test::encode_png({5, 4, 2, 4, 0, 0, px, ""})).find("bit depth 4"),
            std::string::npos);
  EXPECT_NE(error_of(test::encode_png({5, 4, 0, 8, 0, 1, px, ""})).find("interlac"),
            std::string::npos);
  EXPECT_NE(error_of(test::encode_png({5, 4, 0, 8, 5, 0, px, ""})).find("row filter"),
            std::string::npos);
  // A palette image without PLTE, and an index past the palette's end.
  EXPECT_NE(error_of(test::encode_png({5, 4, 3, 8, 0, 0, px, ""})).find("PLTE"), std::string::npos);
  EXPECT_NE(
      error_of(test::encode_png({5, 4, 3, 8, 0, 0, px, std::string(6, '\0')})).find("palette"),
      std::string::npos);
  // 65535 x 65535 announced in the header: refused before any allocation, naming the limit.
  const std::string e = error_of(test::png_announcing(65535, 65535));
  EXPECT_NE(e.find("65535x65535"), std::string::npos) << e;
  EXPECT_NE(e.find("32768"), std::string::npos) << e;
  EXPECT_NE(error_of(test::png_announcing(0, 5)).find("0x5"), std::string::npos);
  EXPECT_EQ(decode(test::png_announcing(1, 1)).pixels.size(), 1u);  // the patch itself is valid
  // A 257 MiB file (sparse: nothing is written) is refused before it is read.
  const fs::path big = temp_file("big.png");
  std::ofstream(big, std::ios::binary) << test::png_announcing(1, 1);
  fs::resize_file(big, std::uintmax_t{257} << 20);
  std::string big_error;
  try {
    io::read_png_gray(big.string());
  } catch (const io::InputError& err) {
    big_error = err.what();
  }
  fs::remove(big);
  EXPECT_NE(big_error.find("at most 256 MiB"), std::string::npos) << big_error;
  EXPECT_NE(error_of("GIF89a").find("PNG"), std::string::npos);
  EXPECT_NE(error_of("").find("PNG"), std::string::npos);
}

}  // namespace
}  // namespace loopscan
