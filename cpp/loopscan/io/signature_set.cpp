#include "loopscan/io/signature_set.hpp"

#include <algorithm>
#include <filesystem>

#include "loopscan/core/config.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"

namespace loopscan::io {
namespace fs = std::filesystem;

SignatureSet load_signature_set(const std::string& path, Method method, const std::string& ids_path,
                                int columns) {
  std::string sig_file = path, id_file = ids_path;
  if (fs::is_directory(path)) {
    sig_file = path + "/signatures.txt";
    if (!fs::exists(sig_file) && fs::exists(sig_file + ".gz")) sig_file += ".gz";
    if (id_file.empty()) id_file = path + "/incoming_id_file.txt";
  } else if (id_file.empty()) {
    id_file = (fs::path(path).parent_path() / "incoming_id_file.txt").string();
  }
  SignatureSet set;
  set.keyframe_ids = read_incoming_ids(id_file);
  const Eigen::MatrixXd all =
      read_matrix_text(sig_file, columns > 0 ? columns : signature_columns(method));
  int rows = rows_per_place(method);
  const auto n = static_cast<Eigen::Index>(set.keyframe_ids.size());
  // Scan Context places may carry lateral versions: 1 + V rows each (ScanContextConfig).
  if (method == Method::ScanContext && n > 0 && all.rows() % n == 0 &&
      all.rows() / n <= 1 + ScanContextConfig::kMaxLateralVersions) {
    rows = static_cast<int>(std::max<Eigen::Index>(1, all.rows() / n));
  }
  if (all.rows() != n * rows) {
    throw InputError(sig_file, 0,
                     std::to_string(set.keyframe_ids.size() * rows) + " rows (" +
                         std::to_string(rows) + " per id in " + id_file + "), found " +
                         std::to_string(all.rows()));
  }
  for (std::size_t i = 0; i < set.keyframe_ids.size(); ++i) {
    set.places.push_back(all.middleRows(static_cast<Eigen::Index>(i) * rows, rows));
  }
  set.frames.assign(set.places.size(), Eigen::Matrix3d::Identity());
  const std::string frames_file = (fs::path(id_file).parent_path() / "frames.txt").string();
  if (fs::exists(frames_file)) {
    const Eigen::MatrixXd f = read_matrix_text(frames_file, 9, 1.0 + 1e-6);
    if (f.rows() != static_cast<Eigen::Index>(set.places.size())) {
      throw InputError(frames_file, 0,
                       std::to_string(set.places.size()) + " rows (one per id in " + id_file +
                           "), found " + std::to_string(f.rows()));
    }
    for (std::size_t i = 0; i < set.frames.size(); ++i) {
      for (int k = 0; k < 9; ++k) set.frames[i](k / 3, k % 3) = f(static_cast<Eigen::Index>(i), k);
      const Eigen::Matrix3d& R = set.frames[i];
      if (!((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-4)) {
        throw InputError(frames_file, i + 1, "9 numbers forming a rotation matrix (row-major)");
      }
    }
  }
  return set;
}

namespace {

// The rows of `all` (one per frame id of `gt_path`) at the keyframe ids.
std::vector<Eigen::Vector3d> at_ids(const std::vector<Eigen::Vector3d>& all,
                                    const std::vector<int>& keyframe_ids,
                                    const std::string& gt_path) {
  std::vector<Eigen::Vector3d> out;
  for (int id : keyframe_ids) {
    if (id < 0 || static_cast<std::size_t>(id) >= all.size()) {
      throw InputError(gt_path, 0,
                       "a line for keyframe id " + std::to_string(id) + " (file has " +
                           std::to_string(all.size()) + " lines)");
    }
    out.push_back(all[static_cast<std::size_t>(id)]);
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector3d> positions_of(const std::vector<int>& keyframe_ids,
                                          const std::string& gt_path, const std::string& format) {
  return at_ids(read_positions(gt_path, gt_format(gt_path, format)), keyframe_ids, gt_path);
}

void attach_positions(SignatureSet& set, const std::string& gt_path, const std::string& format) {
  const GtFormat f = gt_format(gt_path, format);
  set.positions = at_ids(read_positions(gt_path, f), set.keyframe_ids, gt_path);
  set.headings = at_ids(read_headings(gt_path, f), set.keyframe_ids, gt_path);
}

}  // namespace loopscan::io
