#include <loopscan/io/atomic_file.hpp>

#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace loopscan::io {
namespace fs = std::filesystem;

AtomicWriter::AtomicWriter(const std::string& path)
    : path_(path), temp_path_(path + ".tmp." + std::to_string(::getpid())) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  if (ec) {
    throw std::runtime_error("cannot write '" + path + "': cannot create directory '" +
                             parent.string() + "': " + ec.message());
  }
  out_.open(temp_path_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error("cannot write '" + path + "': cannot open temporary file '" +
                             temp_path_ + "'");
  }
}

AtomicWriter::~AtomicWriter() {
  if (!done_) discard();
}

void AtomicWriter::discard() noexcept {
  if (out_.is_open()) out_.close();
  std::error_code ec;
  fs::remove(temp_path_, ec);  // best effort: nothing sensible to do if this fails
  done_ = true;
}

void AtomicWriter::commit() {
  if (done_) throw std::logic_error("AtomicWriter::commit called twice for '" + path_ + "'");
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) {
    discard();
    throw std::runtime_error("cannot write '" + path_ + "': write to temporary file failed");
  }
  std::error_code ec;
  fs::rename(temp_path_, path_, ec);
  if (ec) {
    discard();
    throw std::runtime_error("cannot write '" + path_ + "': rename failed: " + ec.message());
  }
  done_ = true;
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicWriter writer(path);
  writer.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  writer.commit();
}

}  // namespace loopscan::io
