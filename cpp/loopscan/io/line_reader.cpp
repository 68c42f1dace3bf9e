#include <loopscan/io/line_reader.hpp>

#include <zlib.h>

#include <algorithm>
#include <climits>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/limits.hpp>
#include <loopscan/io/parse_numbers.hpp>

namespace loopscan::io {
namespace {

// Large buffers keep zlib and memchr on long runs; the fixtures are tens of MB of text.
constexpr std::size_t kBufferSize = std::size_t{1} << 20;

std::string_view without_cr(const char* data, std::size_t size) {
  if (size > 0 && data[size - 1] == '\r') --size;
  return {data, size};
}

}  // namespace

LineReader::LineReader(const std::string& path) : path_(path) {
  std::error_code ec;
  // zlib would happily open a directory and fail later on read; reject it up front.
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "a readable file");
  file_ = gzopen(path.c_str(), "rb");
  if (file_ == nullptr) throw InputError(path, 0, "a readable file");
  gzbuffer(file_, static_cast<unsigned>(kBufferSize));
  buf_.resize(kBufferSize);
}

LineReader::~LineReader() { close(); }

LineReader::LineReader(LineReader&& other) noexcept
    : path_(std::move(other.path_)),
      file_(std::exchange(other.file_, nullptr)),
      buf_(std::move(other.buf_)),
      begin_(other.begin_),
      scanned_(other.scanned_),
      end_(other.end_),
      line_number_(other.line_number_),
      eof_(other.eof_) {}

LineReader& LineReader::operator=(LineReader&& other) noexcept {
  if (this != &other) {
    close();
    path_ = std::move(other.path_);
    file_ = std::exchange(other.file_, nullptr);
    buf_ = std::move(other.buf_);
    begin_ = other.begin_;
    scanned_ = other.scanned_;
    end_ = other.end_;
    line_number_ = other.line_number_;
    eof_ = other.eof_;
  }
  return *this;
}

void LineReader::close() {
  if (file_ != nullptr) gzclose(file_);
  file_ = nullptr;
}

bool LineReader::next(std::string_view& line) {
  for (;;) {
    const char* start = buf_.data() + begin_;
    const std::size_t avail = end_ - begin_;
    const void* nl = std::memchr(start + scanned_, '\n', avail - scanned_);
    if (nl != nullptr) {
      const std::size_t len = static_cast<std::size_t>(static_cast<const char*>(nl) - start);
      line = without_cr(start, len);
      begin_ += len + 1;
      scanned_ = 0;
      ++line_number_;
      return true;
    }
    scanned_ = avail;
    if (!refill()) {
      if (begin_ == end_) return false;
      line = without_cr(buf_.data() + begin_, end_ - begin_);  // last line has no '\n'
      begin_ = end_;
      scanned_ = 0;
      ++line_number_;
      return true;
    }
  }
}

bool LineReader::refill() {
  if (eof_ || file_ == nullptr) return false;
  // Keep the partial line: move it to the front, grow only when it fills the whole buffer.
  if (begin_ > 0) {
    std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  if (end_ >= limits::kMaxLineBytes) {  // a partial line fills the buffer: no line break
    throw InputError(path_, line_number_ + 1,
                     "lines of at most " + std::to_string(limits::kMaxLineBytes >> 20) +
                         " MiB (no line break in the first " +
                         std::to_string(limits::kMaxLineBytes >> 20) + " MiB of this line)");
  }
  if (end_ == buf_.size()) buf_.resize(std::min(buf_.size() * 2, limits::kMaxLineBytes));
  const std::size_t room = std::min<std::size_t>(buf_.size() - end_, INT_MAX);
  const int n = gzread(file_, buf_.data() + end_, static_cast<unsigned>(room));
  if (n < 0) throw InputError(path_, line_number_ + 1, "readable, uncorrupted (gzip) data");
  if (n == 0) {
    int err = Z_OK;
    gzerror(file_, &err);
    // zlib reports a gzip stream cut short as Z_BUF_ERROR at end of input.
    if (err == Z_BUF_ERROR) {
      throw InputError(path_, line_number_ + 1, "a complete gzip stream (file is truncated)");
    }
    if (err != Z_OK) throw InputError(path_, line_number_ + 1, "readable (gzip) data");
    eof_ = true;
    return false;
  }
  end_ += static_cast<std::size_t>(n);
  return true;
}

bool next_data_line(LineReader& reader, std::string_view& line) {
  if (!reader.next(line)) return false;
  if (!is_blank(line)) return true;
  const std::size_t first_blank = reader.line_number();
  while (reader.next(line)) {
    if (!is_blank(line)) {
      throw InputError(reader.path(), first_blank, "no blank line before the end of the data");
    }
  }
  return false;
}

}  // namespace loopscan::io
