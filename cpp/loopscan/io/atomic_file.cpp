#include <loopscan/io/atomic_file.hpp>

#include <signal.h>
#include <unistd.h>

#include <cstdlib>
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
  stop_for_test("before", path_);
  fs::rename(temp_path_, path_, ec);
  if (ec) {
    discard();
    throw std::runtime_error("cannot write '" + path_ + "': rename failed: " + ec.message());
  }
  stop_for_test("after", path_);
  done_ = true;
}

void stop_for_test(const char* when, const std::string& path) {
  const char* env = std::getenv("LOOPSCAN_TEST_STOP_AT");
  if (!env) return;
  const std::string at = env, prefix = std::string(when) + ":";
  if (at.compare(0, prefix.size(), prefix) != 0) return;
  std::error_code ec;
  const fs::path wanted = fs::absolute(at.substr(prefix.size()), ec).lexically_normal();
  if (!ec && wanted == fs::absolute(path, ec).lexically_normal() && !ec) ::raise(SIGSTOP);
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicWriter writer(path);
  writer.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  writer.commit();
}

}  // namespace loopscan::io
