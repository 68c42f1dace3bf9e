#pragma once
// A command's outputs as one set: readers see the complete old set or the complete new one,
// never a mix, whenever the writer is killed.
#include <functional>
#include <string>

namespace loopscan::io {

// Directory targets: everything is written into a staging directory beside the target
// (`<parent>/.<name>.staging.<pid>`), and commit() swaps it in with one atomic rename
// (renameat2 RENAME_EXCHANGE; two renames plus recovery where the file system lacks it), then
// removes the old set. File targets are written atomically by their writers; for them the set
// only holds the lock and clears stale temporaries.
//
// While the set exists it holds an exclusive lock (`<parent>/.<name>.lock`, flock): a second
// command aimed at the same target is refused at once with an InputError. Under the lock, the
// leftovers of killed runs (staging directories, a File target's `<name>.tmp.<pid>` files) are
// removed and an interrupted swap is rolled back. An existing directory is only replaced when
// it is empty or carries the marker a committed set leaves (`.loopscan`: the command line and
// every entry of the set) and holds nothing else, so a mistyped `--out` never deletes a user's
// files or another command's output nested inside.
class OutputSet {
 public:
  enum class Kind { Directory, File };

  // Throws InputError when the target is locked by another command, is a directory not
  // written by loopscan or holding entries its set does not list, is a mount point, or (File)
  // is a directory or an existing file `is_ours` does not recognise; std::runtime_error when
  // the file system refuses later. `marker` (the command line) starts the set's `.loopscan`
  // file, which then lists every entry of the set.
  OutputSet(const std::string& target, Kind kind, const std::string& marker = "",
            std::function<bool(const std::string&)> is_ours = {});
  ~OutputSet();  // without commit(): the staging directory is removed, the old set stays
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Where to write: the staging directory (Directory) or the target itself (File).
  const std::string& path() const { return write_path_; }
  const std::string& target() const { return target_; }
  // Makes the new set visible in one step and removes the old one. Throws std::runtime_error
  // if the swap fails (the old set is then still in place); calling it twice throws
  // std::logic_error.
  void commit();

  // Name of the marker file every committed directory set holds.
  static const char* marker_name() { return ".loopscan"; }

 private:
  void acquire_lock();
  void clear_stale();
  void check_replaceable() const;
  void release() noexcept;

  std::string target_, parent_, name_, lock_path_, write_path_, marker_;
  Kind kind_;
  std::function<bool(const std::string&)> is_ours_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

}  // namespace loopscan::io
