// describe (one scan) and describe_sequence (a VO export), as `loopscan describe` computes them.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"

namespace loopscan::python {

namespace {

py::array_t<double> describe_scan(const DoubleArray& points, const std::string& method,
                                  const std::string& mode, double range_m) {
  const Cloud cloud = to_cloud(points);
  const SequenceOptions options =
      SequenceOptions::make(parse_method(method), parse_mode(mode), range_m);
  Signature s;
  {
    py::gil_scoped_release release;
    s = describe(options.method, cloud, options.descriptors);
  }
  return from_matrix(s);
}

SequenceSignatures describe_vo(const py::object& poses_in, const py::object& points_in,
                               const std::string& method, const std::string& mode, int threads,
                               double range_m, const py::object& reset_ids) {
  const bool pairs = py::isinstance<py::tuple>(poses_in) && py::isinstance<py::tuple>(points_in) &&
                     py::len(poses_in) == 2 && py::len(points_in) == 2;
  if (!pairs) {
    throw py::value_error(
        "poses and points: expected (ids, T_cam_world) and (ids, xyz_gray) tuples, as "
        "read_sodso_poses / read_sodso_points return");
  }
  const py::tuple poses = poses_in.cast<py::tuple>(), points = points_in.cast<py::tuple>();
  const std::vector<KeyframePose> kf =
      to_poses(poses[0].cast<IntArray>(), poses[1].cast<DoubleArray>());
  const std::vector<IdPoint> pts =
      to_points(points[0].cast<IntArray>(), points[1].cast<DoubleArray>());
  const Mode m = parse_mode(mode);
  if (!(range_m > 0)) throw py::value_error("range_m: expected a positive range in metres");
  SequenceOptions options = SequenceOptions::make(parse_method(method), m, range_m);
  options.threads = threads;
  if (m == Mode::Default) {  // as `describe`: detected unless given
    options.reset_ids =
        reset_ids.is_none() ? detect_vo_resets(kf) : reset_ids.cast<std::vector<int>>();
  }
  py::gil_scoped_release release;
  return describe_sequence(kf, pts, options);
}

}  // namespace

void bind_describe(py::module_& m) {
  py::class_<SequenceSignatures>(m, "SequenceSignatures",
                                 "Signatures of a VO sequence: one per described keyframe.")
      .def_property_readonly(
          "keyframe_ids",
          [](const SequenceSignatures& s) {
            return py::array_t<int>(static_cast<py::ssize_t>(s.keyframe_ids.size()),
                                    s.keyframe_ids.data());
          },
          "int array (P,): the keyframe of each signature")
      .def_property_readonly(
          "signatures",
          [](const SequenceSignatures& s) {
            py::list out;
            for (const Signature& sig : s.signatures) out.append(from_matrix(sig));
            return out;
          },
          "list of P float64 arrays (rows, values): rows = versions of the place (row 0: itself)")
      .def_readonly("imitate_ms", &SequenceSignatures::imitate_ms,
                    "mean ms per described keyframe: crop + filter")
      .def_readonly("describe_ms", &SequenceSignatures::describe_ms,
                    "mean ms per described keyframe: the descriptor (one thread's work)")
      .def("__len__", [](const SequenceSignatures& s) { return s.signatures.size(); })
      .def("__repr__", [](const SequenceSignatures& s) {
        return "<SequenceSignatures: " + std::to_string(s.signatures.size()) + " places, " +
               std::to_string(s.signatures.empty() ? 0 : s.signatures.front().cols()) +
               " values a row>";
      });
  m.def("describe", &describe_scan, py::arg("points"), py::arg("method") = "sc",
        py::arg("mode") = "default", py::arg("range_m") = 45.0,
        "Signature of one imitated scan: points (N, 4) x y z gray in the camera frame "
        "(x right, y down, z ahead), already filtered. Returns a float64 array (rows, values).");
  m.def("describe_sequence", &describe_vo, py::arg("poses"), py::arg("points"),
        py::arg("method") = "sc", py::arg("mode") = "default", py::arg("threads") = 1,
        py::arg("range_m") = 45.0, py::arg("reset_ids") = py::none(),
        "A VO export to place signatures, exactly as `loopscan describe`: poses = (ids (K,), "
        "T_cam_world (K, 3, 4)), points = (ids (N,), xyz_gray (N, 4)) in the VO world frame, "
        "sorted by keyframe id. Default mode detects VO resets unless reset_ids is given.");
}

}  // namespace loopscan::python
