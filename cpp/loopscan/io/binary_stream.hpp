#pragma once
// Internal to loopscan::io: little-endian binary writing and reading with a running CRC-32, for
// the binary file formats (place database, vocabulary). Read errors name the file and offset.
#include <zlib.h>

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

#include "loopscan/io/errors.hpp"

namespace loopscan::io {

static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE types expected");

// Little-endian byte buffer with a running CRC (x86-64 and ARM64 are little-endian; the
// static_assert below keeps a big-endian build from writing wrong files silently).
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "little-endian host expected");

class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  template <typename T>
  void put(const T& v) {
    bytes(&v, sizeof v);
  }
  void bytes(const void* p, std::size_t n) {
    out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    crc_ = crc32(crc_, static_cast<const Bytef*>(p), static_cast<uInt>(n));
  }
  std::uint32_t crc() const { return static_cast<std::uint32_t>(crc_); }

 private:
  std::ostream& out_;
  uLong crc_ = crc32(0L, Z_NULL, 0);
};

class Reader {
 public:
  Reader(std::istream& in, std::string path) : in_(in), path_(std::move(path)) {}
  template <typename T>
  T get(const char* what) {
    T v;
    bytes(&v, sizeof v, what);
    return v;
  }
  void bytes(void* p, std::size_t n, const char* what) {
    if (!in_.read(static_cast<char*>(p), static_cast<std::streamsize>(n))) {
      fail(std::string("unexpected end of file, expected ") + what);
    }
    crc_ = crc32(crc_, static_cast<const Bytef*>(p), static_cast<uInt>(n));
    offset_ += n;
  }
  // "file: byte N: problem", N = the offset reached (the end of the field just read).
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(path_, InputError::Byte{offset_}, problem);
  }
  std::uint32_t crc() const { return static_cast<std::uint32_t>(crc_); }
  std::size_t offset() const { return offset_; }

 private:
  std::istream& in_;
  std::string path_;
  uLong crc_ = crc32(0L, Z_NULL, 0);
  std::size_t offset_ = 0;
};

}  // namespace loopscan::io
