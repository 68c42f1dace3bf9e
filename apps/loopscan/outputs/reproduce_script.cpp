#include "outputs/reproduce_script.hpp"

#include <filesystem>
#include <system_error>

#include "loopscan/io/atomic_file.hpp"
#include "outputs/images.hpp"

namespace loopscan::cli {

namespace fs = std::filesystem;

std::string shell_quoted(const std::string& path) {
  std::string out = "'";
  for (char c : path) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

void write_reproduce_script(const std::string& path, const ReproduceScript& script) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  const std::string binary = ec ? "loopscan" : self.string();
  std::string text = "#!/bin/sh\n# " + script.purpose +
                     "\n# Usage: sh reproduce.sh [OUT]  (LOOPSCAN=/path/to/loopscan to choose the "
                     "binary)\nset -e\nL=\"${LOOPSCAN:-" +
                     binary + "}\"\nD=\"$(cd \"$(dirname \"$0\")" +
                     (script.folder_is_parent ? "/.." : "") +
                     "\" && pwd)\"\nOUT=\"${1:-$(mktemp -d)}\"\necho \"recomputing into $OUT\"\n";
  for (const std::string& line : script.lines) text += line + "\n";
  fs::create_directories(fs::path(path).parent_path());
  io::write_file_atomic(path, text);
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
}

// describe + evaluate of the written sessions with the demo's configuration: the table's
// numbers, digit for digit.
ReproduceScript demo_script(int threads) {
  const std::string t = std::to_string(threads);
  const std::string config = " --config \"$D/config.yaml\"";
  return {
      "Recomputes the table `loopscan demo` printed from the drives it wrote.",
      true,
      {"for m in sc m2dp delight; do", "  for s in summer winter; do",
       "    \"$L\" describe --method $m" + config + " --threads " + t +
           " --poses \"$D/$s/poses_history_file.txt\" --points \"$D/$s/pts_history_file.txt\" "
           "--out \"$OUT/$m-$s\" >/dev/null",
       "  done",
       "  \"$L\" evaluate" + config + " --signatures \"$OUT/$m-summer\" --gt \"$D/summer/gt.txt\" "
       "--out \"$OUT/$m-same\"",
       "  \"$L\" evaluate" + config + " --signatures \"$OUT/$m-winter\" --gt \"$D/winter/gt.txt\" "
       "--against \"$OUT/$m-summer\" --gt2 \"$D/summer/gt.txt\" --out \"$OUT/$m-cross\"",
       "done"}};
}

// describe (+ a cmp with the run's signatures) and evaluate of what the run wrote: the table.
ReproduceScript run_script(const std::vector<MethodRun>& runs, const std::string& kitti,
                           const std::string& vocab_path, const std::string& gt_path) {
  ReproduceScript script{
      "Recomputes the table `loopscan run` printed from the files it wrote.", false, {}};
  std::string places;  // the places of the image baselines, as in run_all
  for (const MethodRun& r : runs) {
    const std::string out = "\"$OUT/" + r.name + "\"";
    // Each method's folder holds the configuration it was described and evaluated with.
    const std::string config = " --config \"$D/" + r.name + "/config.yaml\"";
    if (!is_image_method(r.name)) {
      if (places.empty() && !r.keyframe_ids.empty()) places = out;
      script.lines.push_back("\"$L\" describe --method " + r.name + config +
                             " --poses \"$D/vo/poses_history_file.txt\" --points "
                             "\"$D/vo/pts_history_file.txt\" --out " +
                             out + " >/dev/null");
      script.lines.push_back("cmp " + out + "/signatures.txt \"$D/" + r.name + "/signatures.txt\"");
    } else if (r.evaluated && !places.empty()) {
      const std::string vocab =
          r.name == "bow" ? " --vocab " + shell_quoted(fs::absolute(vocab_path).string()) : "";
      script.lines.push_back("\"$L\" describe --method " + r.name + config + " --kitti " +
                             shell_quoted(fs::absolute(kitti).string()) + " --keyframes " + places +
                             vocab + " --out " + out + " >/dev/null");
    }
    if (r.evaluated && (!is_image_method(r.name) || !places.empty())) {
      script.lines.push_back("\"$L\" evaluate" + config + " --signatures " + out +
                             " --gt " + shell_quoted(fs::absolute(gt_path).string()) +
                             " --out \"$OUT/" + r.name + "-evaluation\"");
    }
  }
  return script;
}

}  // namespace loopscan::cli
