#include "outputs/signatures.hpp"

#include <filesystem>

#include "cli/configuration.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"

namespace loopscan::cli {
namespace {

Eigen::MatrixXd stack(const std::vector<Signature>& sigs, Method method) {
  // Scan Context places with lateral versions have more than one row.
  const Eigen::Index rows = sigs.empty() ? rows_per_place(method) : sigs.front().rows();
  const Eigen::Index cols = sigs.empty() ? signature_columns(method) : sigs.front().cols();
  Eigen::MatrixXd all(static_cast<Eigen::Index>(sigs.size()) * rows, cols);
  for (std::size_t i = 0; i < sigs.size(); ++i) all.middleRows(i * rows, rows) = sigs[i];
  return all;
}

}  // namespace

void write_signatures(const std::string& dir, const SequenceSignatures& result,
                      const Configuration& c) {
  const Method method = c.method;
  std::filesystem::create_directories(dir);
  io::write_matrix_text(dir + "/signatures.txt", stack(result.signatures, method));
  io::write_incoming_ids(dir + "/incoming_id_file.txt", result.keyframe_ids);
  // Descriptor axes per place (row-major 3x3): `db` turns Scan Context shifts into yaw with them.
  Eigen::MatrixXd frames(static_cast<Eigen::Index>(result.frames.size()), 9);
  for (std::size_t i = 0; i < result.frames.size(); ++i) {
    for (int k = 0; k < 9; ++k)
      frames(static_cast<Eigen::Index>(i), k) = result.frames[i](k / 3, k % 3);
  }
  io::write_matrix_text(dir + "/frames.txt", frames);
  write_used_configuration(dir, c);
}

SequenceSignatures describe_as_written(const std::vector<KeyframePose>& poses,
                                       const std::vector<IdPoint>& points, SequenceOptions options,
                                       const Configuration& c) {
  if (c.mode == Mode::Default) options.reset_ids = detect_vo_resets(poses, c.reset_jump_m);
  SequenceSignatures result = describe_sequence(poses, points, options);
  for (Signature& s : result.signatures) s = io::as_written(s);
  return result;
}

}  // namespace loopscan::cli
