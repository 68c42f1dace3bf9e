#include <loopscan/io/output_set.hpp>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <system_error>
#include <vector>

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

// Follows symbolic links at `p` (relative ones from the link's directory), also to a target
// that does not exist yet.
fs::path resolve_links(fs::path p) {
  std::error_code ec;
  for (int hops = 0; hops < 40 && fs::is_symlink(p, ec); ++hops) {
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) break;
    p = (to.is_absolute() ? to : p.parent_path() / to).lexically_normal();
  }
  return p;
}

// Every entry below `dir` (directories too), relative, sorted; the marker file left out.
std::vector<std::string> entries_below(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    const std::string rel = fs::relative(it->path(), dir, ec).generic_string();
    if (rel != OutputSet::marker_name()) out.push_back(rel);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Entries of the set at `dir` that its marker does not list: another command's output nested
// in it, or a user's files. Empty when the marker lists none (a set from before the lists).
std::vector<std::string> foreign_entries(const fs::path& dir) {
  std::ifstream in(dir / OutputSet::marker_name());
  std::string line;
  std::getline(in, line);  // the command line
  std::set<std::string> listed;
  while (std::getline(in, line)) listed.insert(line);
  std::vector<std::string> foreign;
  if (listed.empty()) return foreign;
  for (const std::string& e : entries_below(dir)) {
    if (!listed.count(e)) foreign.push_back(e);
  }
  return foreign;
}

[[noreturn]] void refuse_foreign(const std::string& target,
                                 const std::vector<std::string>& foreign) {
  std::string names;
  for (std::size_t i = 0; i < foreign.size() && i < 3; ++i) names += (i ? ", " : "") + foreign[i];
  if (foreign.size() > 3) names += " and " + std::to_string(foreign.size() - 3) + " more";
  throw InputError(target, 0,
                   "only the files of the output set it holds (it also holds " + names +
                       ", written by another command or by hand, which replacing the set would "
                       "delete: move them elsewhere or choose another output directory)");
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

OutputSet::OutputSet(const std::string& target, Kind kind, const std::string& marker,
                     std::function<bool(const std::string&)> is_ours)
    : marker_(marker), kind_(kind), is_ours_(std::move(is_ours)) {
  fs::path p = fs::path(target).lexically_normal();
  if (p.has_relative_path() && p.filename().empty()) {  // "out/" -> "out"
    if (kind == Kind::File) throw InputError(target, 0, "a file path (not one ending in '/')");
    p = p.parent_path();
  }
  const std::string name = p.filename().string();
  if (target.empty() || name.empty() || name == "." || name == "..") {
    throw InputError(target, 0, "an output path that names a directory or file (not '.' or '..')");
  }
  p = resolve_links(p);  // write what a link points to, even one not created yet
  target_ = p.string();
  name_ = p.filename().string();
  parent_ = p.has_parent_path() ? p.parent_path().string() : ".";
  std::error_code ec;
  fs::create_directories(parent_, ec);
  if (ec) {
    throw InputError(
        target_, 0,
        "a directory that can be created (cannot create '" + parent_ + "': " + ec.message() + ")");
  }
  struct stat parent_st {};
  struct stat target_st {};
  if (::stat(parent_.c_str(), &parent_st) == 0 && ::stat(target_.c_str(), &target_st) == 0 &&
      parent_st.st_dev != target_st.st_dev) {
    throw InputError(target_, 0,
                     "an output on the same file system as its parent directory (it is a mount "
                     "point, where a new set cannot be swapped in: use a directory inside it, "
                     "e.g. " +
                         target_ + "/run)");
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
    if (lock_fd_ < 0) {
      throw InputError(target_, 0,
                       "a writable parent directory (cannot create '" + lock_path_ +
                           "': " + std::strerror(errno) + ")");
    }
    if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
      if (errno != EWOULDBLOCK) {
        const int err = errno;
        ::close(lock_fd_);
        lock_fd_ = -1;
        errno = err;
        fail_system(target_, "cannot lock '" + lock_path_ + "'");
      }
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
               (starts_with(n, old) && all_digits(n, old.size()))) {
      std::error_code ignored;
      fs::remove_all(e.path(), ignored);
    } else if (kind_ == Kind::File && starts_with(n, temp) && all_digits(n, temp.size()) &&
               e.is_regular_file(ec)) {
      std::error_code ignored;  // an AtomicWriter's temporary of a killed run
      fs::remove(e.path(), ignored);
    }
  }
}

void OutputSet::check_replaceable() const {
  std::error_code ec;
  const fs::file_status st = fs::status(target_, ec);
  if (!fs::exists(st)) return;
  if (kind_ == Kind::File) {
    if (fs::is_directory(st)) throw InputError(target_, 0, "a file path (it is a directory)");
    if (is_ours_ && fs::file_size(target_, ec) > 0 && !is_ours_(target_)) {
      throw InputError(target_, 0,
                       "a file of the kind this command writes, to replace (it holds something "
                       "else: remove it or choose another output file)");
    }
    return;
  }
  if (!fs::is_directory(st)) throw InputError(target_, 0, "a directory (it is a file)");
  if (fs::exists(fs::path(target_) / marker_name())) {
    const std::vector<std::string> foreign = foreign_entries(target_);
    if (!foreign.empty()) refuse_foreign(target_, foreign);
    return;
  }
  if (fs::is_empty(target_, ec)) return;
  throw InputError(target_, 0,
                   "an empty directory or one written by loopscan (it holds other files and no " +
                       std::string(marker_name()) +
                       " marker; remove it or choose another output directory)");
}

void OutputSet::commit() {
  if (committed_) throw std::logic_error("OutputSet::commit called twice for '" + target_ + "'");
  if (kind_ == Kind::Directory) {
    std::string listing = marker_ + "\n";  // the command line, then every entry of the set
    for (const std::string& e : entries_below(write_path_)) listing += e + "\n";
    write_file_atomic(write_path_ + "/" + marker_name(), listing);
    std::error_code ec;
    // Something written into the old set meanwhile (a command on a directory inside it):
    // swapping would delete it.
    if (fs::exists(fs::path(target_) / marker_name(), ec)) {
      const std::vector<std::string> foreign = foreign_entries(target_);
      if (!foreign.empty()) refuse_foreign(target_, foreign);
    }
    stop_for_test("before", target_);
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
    stop_for_test("after", target_);
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
