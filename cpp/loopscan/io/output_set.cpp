#include <loopscan/io/output_set.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <loopscan/io/atomic_file.hpp>
#include <loopscan/io/errors.hpp>

namespace loopscan::io {
namespace fs = std::filesystem;
namespace {

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

bool all_digits(const std::string& s, std::size_t from) {
  if (from >= s.size()) return false;
  for (std::size_t i = from; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
  }
  return true;
}

[[noreturn]] void fail_system(const std::string& target, const std::string& what) {
  throw std::runtime_error("cannot write '" + target + "': " + what + ": " + std::strerror(errno));
}

// Swaps two directory entries atomically; false when the file system cannot.
bool exchange(const std::string& a, const std::string& b) {
  // Tests take the fallback path on purpose (file systems without it: older NFS, some FUSE).
  if (std::getenv("LOOPSCAN_NO_RENAME_EXCHANGE") != nullptr) return false;
  if (::renameat2(AT_FDCWD, a.c_str(), AT_FDCWD, b.c_str(), RENAME_EXCHANGE) == 0) return true;
  if (errno == EINVAL || errno == ENOSYS || errno == ENOTSUP) return false;
  fail_system(b, "cannot swap in the new output set");
}

}  // namespace

OutputSet::OutputSet(const std::string& target, Kind kind, const std::string& marker)
    : marker_(marker), kind_(kind) {
  fs::path p = fs::path(target).lexically_normal();
  if (p.has_relative_path() && p.filename().empty()) p = p.parent_path();  // "out/" -> "out"
  const std::string name = p.filename().string();
  if (target.empty() || name.empty() || name == "." || name == "..") {
    throw InputError(target, 0, "an output path that names a directory or file (not '.' or '..')");
  }
  std::error_code ec;
  if (fs::is_symlink(p, ec)) p = fs::canonical(p, ec);  // replace what the link points to
  target_ = p.string();
  name_ = p.filename().string();
  parent_ = p.has_parent_path() ? p.parent_path().string() : ".";
  fs::create_directories(parent_, ec);
  if (ec) {
    throw std::runtime_error("cannot write '" + target_ + "': cannot create directory '" + parent_ +
                             "': " + ec.message());
  }
  lock_path_ = parent_ + "/." + name_ + ".lock";
  acquire_lock();
  try {
    clear_stale();
    check_replaceable();
    if (kind_ == Kind::File) {
      write_path_ = target_;
    } else {
      write_path_ = parent_ + "/." + name_ + ".staging." + std::to_string(::getpid());
      fs::remove_all(write_path_, ec);
      if (!fs::create_directory(write_path_, ec) || ec) {
        throw std::runtime_error("cannot write '" + target_ + "': cannot create '" + write_path_ +
                                 "': " + ec.message());
      }
    }
  } catch (...) {
    release();
    throw;
  }
}

OutputSet::~OutputSet() {
  if (!committed_ && kind_ == Kind::Directory && !write_path_.empty()) {
    std::error_code ec;
    fs::remove_all(write_path_, ec);  // best effort; the next run clears what is left
  }
  release();
}

void OutputSet::acquire_lock() {
  // The lock file is unlinked on release, so a lock taken on a file that has since been
  // replaced (or removed) is retried on the file now at the path.
  for (;;) {
    lock_fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock_fd_ < 0) fail_system(target_, "cannot create the lock file '" + lock_path_ + "'");
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
      char owner[32] = {0};
      const ssize_t n = ::pread(lock_fd_, owner, sizeof owner - 1, 0);
      ::close(lock_fd_);
      lock_fd_ = -1;
      const std::string pid = n > 0 ? std::string(owner, static_cast<std::size_t>(n)) : "?";
      throw InputError(target_, 0,
                       "no other loopscan command writing it (pid " + pid + " holds '" +
                           lock_path_ + "'; wait for it or choose another output)");
    }
    struct stat held {
    }, now{};
    if (::fstat(lock_fd_, &held) == 0 && ::stat(lock_path_.c_str(), &now) == 0 &&
        held.st_ino == now.st_ino && held.st_dev == now.st_dev) {
      const std::string pid = std::to_string(::getpid());
      if (::ftruncate(lock_fd_, 0) == 0) {
        [[maybe_unused]] const ssize_t w = ::pwrite(lock_fd_, pid.data(), pid.size(), 0);
      }
      return;
    }
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
}

void OutputSet::clear_stale() {
  // Only a process holding the lock writes these names, so under the lock they are leftovers.
  const std::string staging = "." + name_ + ".staging.", old = "." + name_ + ".old.";
  const std::string temp = name_ + ".tmp.";
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(parent_, ec)) {
    const std::string n = e.path().filename().string();
    if (starts_with(n, old) && all_digits(n, old.size()) && !fs::exists(target_)) {
      fs::rename(e.path(), target_, ec);  // a swap cut between its two renames: roll back
    } else if ((starts_with(n, staging) && all_digits(n, staging.size())) ||
               (starts_with(n, old) && all_digits(n, old.size())) ||
               (starts_with(n, temp) && all_digits(n, temp.size()))) {
      std::error_code ignored;
      fs::remove_all(e.path(), ignored);
    }
  }
}

void OutputSet::check_replaceable() const {
  std::error_code ec;
  const fs::file_status st = fs::status(target_, ec);
  if (!fs::exists(st)) return;
  if (kind_ == Kind::File) {
    if (fs::is_directory(st)) throw InputError(target_, 0, "a file path (it is a directory)");
    return;
  }
  if (!fs::is_directory(st)) throw InputError(target_, 0, "a directory (it is a file)");
  if (fs::exists(fs::path(target_) / marker_name()) || fs::is_empty(target_, ec)) return;
  throw InputError(target_, 0,
                   "an empty directory or one written by loopscan (it holds other files and no " +
                       std::string(marker_name()) +
                       " marker; remove it or choose another output directory)");
}

void OutputSet::commit() {
  if (committed_) throw std::logic_error("OutputSet::commit called twice for '" + target_ + "'");
  if (kind_ == Kind::Directory) {
    write_file_atomic(write_path_ + "/" + marker_name(), marker_ + "\n");
    std::error_code ec;
    if (!fs::exists(target_, ec)) {
      if (::rename(write_path_.c_str(), target_.c_str()) != 0) {
        fail_system(target_, "cannot move the new output set into place");
      }
    } else if (!exchange(write_path_, target_)) {
      // No RENAME_EXCHANGE here: move the old set aside, then the new one in. A kill between
      // the two leaves `.<name>.old.<pid>`, which the next run renames back.
      const std::string aside = parent_ + "/." + name_ + ".old." + std::to_string(::getpid());
      if (::rename(target_.c_str(), aside.c_str()) != 0)
        fail_system(target_, "cannot move the old set");
      if (::rename(write_path_.c_str(), target_.c_str()) != 0) {
        ::rename(aside.c_str(), target_.c_str());
        fail_system(target_, "cannot move the new output set into place");
      }
      ::rename(aside.c_str(), write_path_.c_str());
    }
    fs::remove_all(write_path_, ec);  // the old set, now at the staging path
  }
  committed_ = true;
  release();
}

void OutputSet::release() noexcept {
  if (lock_fd_ < 0) return;
  ::unlink(lock_path_.c_str());
  ::close(lock_fd_);
  lock_fd_ = -1;
}

}  // namespace loopscan::io
