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
  Places places;
  py::array_t<double> positions;
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
        return from_positions(io::read_positions(path, io::gt_format(path, format)));
      },
      py::arg("path"), py::arg("format") = "auto",
      "Ground truth, one position a line: KITTI poses (camera-to-world 3x4) or RobotCar GPS "
      "(northing easting down), told apart by the numbers a line ('auto'), or 'kitti' / "
      "'robotcar' -> float64 (N, 3).");
  py::class_<LoadedSignatures> cls(m, "SignatureSet", "A `describe` output: signatures and ids.");
  bind_places<LoadedSignatures>(cls);
  cls.def_readonly("positions", &LoadedSignatures::positions,
                   "ground-truth position of each place (empty without gt)")
      .def("__repr__", [](const LoadedSignatures& s) {
        return "<SignatureSet: " + std::to_string(py::len(s.places.signatures)) + " places" +
               (s.positions.shape(0) == 0 ? "" : ", with positions") + ">";
      });
  m.def(
      "read_signatures",
      [](const std::string& path, const std::string& method, const std::string& gt,
         const std::string& gt_format) {
        io::SignatureSet set = io::load_signature_set(path, parse_method(method));
        if (!gt.empty()) io::attach_positions(set, gt, gt_format);
        return LoadedSignatures{places_of(set.places, set.keyframe_ids, set.frames),
                                from_positions(set.positions)};
      },
      py::arg("path"), py::arg("method") = "sc", py::arg("gt") = "", py::arg("gt_format") = "auto",
      "A `describe` output directory (signatures.txt + incoming_id_file.txt); gt: a ground-truth "
      "file whose line = keyframe id gives each place's position.");
}

}  // namespace loopscan::python
