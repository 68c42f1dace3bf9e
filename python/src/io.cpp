// The file readers: SO-DSO exports, ground truth, `describe` outputs. File errors come back as
// RuntimeError with the file, line and what was expected.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/signature_set.hpp"
#include "loopscan/io/sodso.hpp"

namespace loopscan::python {

namespace {

struct LoadedSignatures {  // a `describe` output directory, with positions when asked
  io::SignatureSet set;
};

}  // namespace

void bind_io(py::module_& m) {
  m.def(
      "read_sodso_poses",
      [](const std::string& path) { return from_poses(io::read_sodso_poses(path)); },
      py::arg("path"), "poses_history_file.txt -> (ids int (K,), T_cam_world float64 (K, 3, 4)).");
  m.def(
      "read_sodso_points",
      [](const std::string& path) { return from_points(io::read_sodso_points(path)); },
      py::arg("path"),
      "pts_history_file.txt[.gz] -> (ids int (N,), xyz_gray float64 (N, 4)), world frame.");
  m.def(
      "read_positions",
      [](const std::string& path, const std::string& format) {
        return from_positions(io::read_positions(path, io::parse_gt_format(format)));
      },
      py::arg("path"), py::arg("format") = "kitti",
      "Ground truth, one position a line: KITTI poses (camera-to-world 3x4) or RobotCar GPS "
      "(northing easting down) -> float64 (N, 3).");
  py::class_<LoadedSignatures>(m, "SignatureSet", "A `describe` output: signatures and ids.")
      .def_property_readonly("signatures",
                             [](const LoadedSignatures& s) {
                               py::list out;
                               for (const Signature& sig : s.set.places)
                                 out.append(from_matrix(sig));
                               return out;
                             })
      .def_property_readonly("keyframe_ids",
                             [](const LoadedSignatures& s) {
                               return py::array_t<int>(
                                   static_cast<py::ssize_t>(s.set.keyframe_ids.size()),
                                   s.set.keyframe_ids.data());
                             })
      .def_property_readonly(
          "positions", [](const LoadedSignatures& s) { return from_positions(s.set.positions); },
          "ground-truth position of each place (empty without gt)")
      .def("__len__", [](const LoadedSignatures& s) { return s.set.places.size(); })
      .def("__repr__", [](const LoadedSignatures& s) {
        return "<SignatureSet: " + std::to_string(s.set.places.size()) + " places" +
               (s.set.positions.empty() ? "" : ", with positions") + ">";
      });
  m.def(
      "read_signatures",
      [](const std::string& path, const std::string& method, const std::string& gt,
         const std::string& gt_format) {
        LoadedSignatures s{io::load_signature_set(path, parse_method(method))};
        if (!gt.empty()) io::attach_positions(s.set, gt, gt_format);
        return s;
      },
      py::arg("path"), py::arg("method") = "sc", py::arg("gt") = "", py::arg("gt_format") = "kitti",
      "A `describe` output directory (signatures.txt + incoming_id_file.txt); gt: a ground-truth "
      "file whose line = keyframe id gives each place's position.");
}

}  // namespace loopscan::python
