#include "mutate.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace loopscan::fuzz {
namespace {

using Rng = std::mt19937_64;

std::size_t pick(Rng& rng, std::size_t n) {
  return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
}

// Tokens that parse but must not be accepted, or nearly parse.
const std::array<const char*, 24> kHostileTokens = {
    "nan",    "-nan",       "inf",        "-inf",        "1e308",
    "-1e308", "1e400",      "1e-320",     "0",           "-0",
    "-1",     "2147483647", "2147483648", "-2147483649", "99999999999999999999",
    "0x10",   "1e",         "+",          "--1",         "1..2",
    "",       "\xd9\xa1",   "3.4e38",     "1e30"};

// Boundary values for binary fields of 1, 2, 4 or 8 bytes.
const std::array<std::uint64_t, 12> kHostileWords = {0,
                                                     1,
                                                     0x7F,
                                                     0x80,
                                                     0xFF,
                                                     0x7FFF,
                                                     0xFFFF,
                                                     0x7FFFFFFF,
                                                     0x80000000,
                                                     0xFFFFFFFF,
                                                     0x7FF0000000000000ULL /* +inf as f64 */,
                                                     0xFFFFFFFFFFFFFFFFULL};

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t nl = s.find('\n', start);
    if (nl == std::string::npos) {
      if (start < s.size()) lines.push_back(s.substr(start));
      break;
    }
    lines.push_back(s.substr(start, nl - start));
    start = nl + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

void replace_token(std::string& s, Rng& rng) {
  // A random blank-separated token becomes a hostile one.
  std::vector<std::pair<std::size_t, std::size_t>> tokens;
  for (std::size_t i = 0; i < s.size();) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\n' || s[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\n' && s[i] != '\t') ++i;
    if (i > start) tokens.emplace_back(start, i - start);
  }
  if (tokens.empty()) return;
  const auto [at, len] = tokens[pick(rng, tokens.size())];
  std::string with = kHostileTokens[pick(rng, kHostileTokens.size())];
  if (pick(rng, 20) == 0) with = std::string(1 + pick(rng, 2000), '9');  // a very long number
  s.replace(at, len, with);
}

// A numeric token becomes another valid number (scaled, negated, zero, tiny, large): the
// input still parses, so what follows the reader (geometry, descriptors, matching) runs on it.
void perturb_number(std::string& s, Rng& rng) {
  std::vector<std::pair<std::size_t, std::size_t>> numbers;
  for (std::size_t i = 0; i < s.size();) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\n' || s[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\n' && s[i] != '\t') ++i;
    const std::string token = s.substr(start, i - start);
    char* end = nullptr;
    if (!token.empty()) {
      std::strtod(token.c_str(), &end);
      if (*end == '\0') numbers.emplace_back(start, i - start);
    }
  }
  if (numbers.empty()) return;
  const auto [at, len] = numbers[pick(rng, numbers.size())];
  const double v = std::strtod(s.substr(at, len).c_str(), nullptr);
  const std::array<double, 8> factors = {-1, 0, 2, 0.5, 1e-9, 1e3, 1e6, -1e4};
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g",
                pick(rng, 3) ? v * factors[pick(rng, factors.size())] : double(pick(rng, 200)));
  s.replace(at, len, buf);
}

void mutate_lines(std::string& s, Rng& rng) {
  std::vector<std::string> lines = split_lines(s);
  if (lines.empty()) return;
  const std::size_t i = pick(rng, lines.size()), j = pick(rng, lines.size());
  switch (pick(rng, 7)) {
    case 0:
      lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(i));
      break;
    case 1:
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[j]);
      break;
    case 2:
      std::swap(lines[i], lines[j]);
      break;
    case 3:
      lines[i] = lines[i].substr(0, pick(rng, lines[i].size() + 1));
      break;
    case 4:
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), "");
      break;
    case 5:
      lines[i] += pick(rng, 2) ? "\r" : " 7";
      break;
    default:
      lines[i] += std::string(1, static_cast<char>(pick(rng, 256)));
      break;
  }
  s = join_lines(lines);
}

void mutate_bytes(std::string& s, const Target& t, Rng& rng) {
  switch (pick(rng, 7)) {
    case 0:  // flip a bit
      if (!s.empty()) s[pick(rng, s.size())] ^= static_cast<char>(1 << pick(rng, 8));
      break;
    case 1:  // cut
      s.resize(pick(rng, s.size() + 1));
      break;
    case 2: {  // junk appended or inserted
      std::string junk(1 + pick(rng, 64), '\0');
      for (char& c : junk) c = static_cast<char>(pick(rng, 256));
      s.insert(pick(rng, s.size() + 1), junk);
      break;
    }
    case 3: {  // a boundary value over a field; binary headers are hit more often
      const std::size_t width = std::size_t{1} << pick(rng, 4);
      if (s.size() < width) break;
      const std::size_t limit = t.format == Format::Binary && pick(rng, 2)
                                    ? std::min<std::size_t>(s.size(), 64)
                                    : s.size();
      const std::size_t at = pick(rng, limit - width + 1);
      const std::uint64_t v = kHostileWords[pick(rng, kHostileWords.size())];
      std::memcpy(&s[at], &v, width);
      break;
    }
    case 4: {  // a random byte
      if (!s.empty()) s[pick(rng, s.size())] = static_cast<char>(pick(rng, 256));
      break;
    }
    case 5: {  // a block duplicated (repeated records, chunks)
      if (s.empty()) break;
      const std::size_t a = pick(rng, s.size()),
                        n = 1 + pick(rng, std::min<std::size_t>(256, s.size() - a));
      s.insert(pick(rng, s.size() + 1), s.substr(a, n));
      break;
    }
    default: {  // a float field overwritten with NaN / inf / huge
      const std::array<float, 4> values = {std::numeric_limits<float>::quiet_NaN(),
                                           std::numeric_limits<float>::infinity(), -3.4e38f, 1e30f};
      if (s.size() < 4) break;
      const float v = values[pick(rng, values.size())];
      std::memcpy(&s[pick(rng, s.size() - 3)], &v, 4);
      break;
    }
  }
}

}  // namespace

void fix_trailing_crc(std::string& s) {
  if (s.size() < 4) return;
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size() - 4)));
  std::memcpy(&s[s.size() - 4], &crc, 4);
}

void fix_png_crcs(std::string& s) {
  for (std::size_t at = 8; at + 12 <= s.size();) {
    const auto* p = reinterpret_cast<const unsigned char*>(s.data() + at);
    const std::uint32_t len = (std::uint32_t(p[0]) << 24) | (p[1] << 16) | (p[2] << 8) | p[3];
    if (len > s.size() - at - 12) return;
    const auto crc = static_cast<std::uint32_t>(crc32(0L, p + 4, len + 4));
    for (int k = 0; k < 4; ++k)
      s[at + 8 + len + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
    at += 12 + len;
  }
}

std::string mutate(const std::string& bytes, const Target& t, Rng& rng) {
  std::string s = bytes;
  const std::size_t n = 1 + pick(rng, 4);
  for (std::size_t k = 0; k < n; ++k) {
    if (t.format == Format::Text && pick(rng, 4) != 0) {
      const std::size_t kind = pick(rng, 3);
      if (kind == 0) {
        replace_token(s, rng);
      } else if (kind == 1) {
        perturb_number(s, rng);
      } else {
        mutate_lines(s, rng);
      }
    } else {
      mutate_bytes(s, t, rng);
    }
  }
  if (t.format == Format::Text && pick(rng, 200) == 0) {
    s += std::string(std::size_t{5} << 20, '1');  // a line past the reader's bound
  }
  if (pick(rng, 2)) {  // half the cases get valid checksums, to reach the value checks
    if (t.trailing_crc) fix_trailing_crc(s);
    if (t.png_chunks) fix_png_crcs(s);
  }
  return s;
}

}  // namespace loopscan::fuzz
