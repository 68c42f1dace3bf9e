#pragma once
// Loading a described sequence: signatures + keyframe ids (+ ground-truth positions).
#include <string>
#include <vector>

#include "loopscan/core/signature.hpp"

namespace loopscan::io {

struct SignatureSet {
  std::vector<Signature> places;
  std::vector<int> keyframe_ids;
  std::vector<Eigen::Vector3d> positions;  // ground truth of each place
  std::vector<Eigen::Vector3d> headings;   // ground-truth forward direction of each place
  // Descriptor axes in the camera frame (frames.txt of a describe output; identity without).
  std::vector<Eigen::Matrix3d> frames;
};

// `path` is a `describe` output directory (signatures.txt[.gz] + incoming_id_file.txt, and
// frames.txt when present) or a signature file (then `ids_path`, or incoming_id_file.txt next
// to it, gives the ids). Every file is checked against the others (rows per id, one frame per
// id, each frame a rotation); errors are InputErrors naming the file. `columns`: the width of a
// signature row (0: the method's default parameters').
SignatureSet load_signature_set(const std::string& path, Method method,
                                const std::string& ids_path = "", int columns = 0);

// Ground-truth positions of keyframe ids from a KITTI pose / RobotCar GPS file (line = id);
// `format`: kitti, robotcar or auto (io::detect_gt_format).
std::vector<Eigen::Vector3d> positions_of(const std::vector<int>& keyframe_ids,
                                          const std::string& gt_path,
                                          const std::string& format = "auto");

// Positions and headings of the places from a KITTI pose / RobotCar GPS file, indexed by keyframe
// id.
void attach_positions(SignatureSet& set, const std::string& gt_path,
                      const std::string& format = "auto");

}  // namespace loopscan::io
