#pragma once
// `reproduce.sh`: the `loopscan describe` / `evaluate` commands that recompute, from the files a
// command wrote, the numbers it printed.
#include <string>
#include <vector>

#include "outputs/run_report.hpp"

namespace loopscan::cli {

// One shell line a string; "$L" is the loopscan binary, "$D" the folder the script is written
// to (or its parent, see below) and "$OUT" the folder the commands write into.
struct ReproduceScript {
  std::string purpose;            // a comment line at the top
  bool folder_is_parent = false;  // "$D" = the script's folder's parent (demo/report/..)
  std::vector<std::string> lines;
};

// A path quoted for the shell.
std::string shell_quoted(const std::string& path);

// Writes `path` (executable). The binary defaults to the one running now ($LOOPSCAN overrides
// it); "$OUT" is the script's first argument, else a fresh temporary folder.
void write_reproduce_script(const std::string& path, const ReproduceScript& script);

// The demo's: per method `describe` of summer/ and winter/, `evaluate` same-season and
// winter --against summer.
ReproduceScript demo_script(int threads);

// The run's: `describe` of DIR3/vo/ (and a `cmp` with the run's signatures), the image
// baselines at the same places, `evaluate` of every evaluated method.
ReproduceScript run_script(const std::vector<MethodRun>& runs, const std::string& kitti,
                           const std::string& vocab_path, const std::string& gt_path);

}  // namespace loopscan::cli
