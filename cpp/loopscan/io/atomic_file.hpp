#pragma once
// Atomic file replacement: readers never see a half-written output file.
#include <fstream>
#include <ostream>
#include <string>

namespace loopscan::io {

// Writes `content` to `path + ".tmp.<pid>"` in the same directory, then renames it over `path`.
// Parent directories are created as needed. On failure the temp file is removed and a
// std::runtime_error naming `path` is thrown.
void write_file_atomic(const std::string& path, const std::string& content);

// Streaming variant for large outputs. Nothing appears at `path` until commit(); destroying
// the writer without commit() removes the temp file.
class AtomicWriter {
 public:
  explicit AtomicWriter(const std::string& path);
  ~AtomicWriter();
  AtomicWriter(const AtomicWriter&) = delete;
  AtomicWriter& operator=(const AtomicWriter&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, closes and renames the temp file over `path`; throws std::runtime_error on failure
  // (temp file removed). Calling it twice throws std::logic_error.
  void commit();

  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return temp_path_; }

 private:
  void discard() noexcept;

  std::string path_;
  std::string temp_path_;
  std::ofstream out_;
  bool done_ = false;
};

// The kill test's hook: with LOOPSCAN_TEST_STOP_AT="<when>:<path>" in the environment (when:
// before or after), a writer stops itself (SIGSTOP) just before or just after the rename that
// makes `path` visible, so that the test kills it at the moment that decides between the old
// output and the new one. Without the variable (every other run), nothing happens.
void stop_for_test(const char* when, const std::string& path);

}  // namespace loopscan::io
