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

// A described sequence: its places and the mean stage times.
struct DescribedSequence {
  Places places;
  double imitate_ms = 0, describe_ms = 0;
};

DescribedSequence describe_vo(const py::object& poses_in, const py::object& points_in,
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
  SequenceOptions options = SequenceOptions::make(parse_method(method), m, range_m);
  options.threads = threads;
  if (m == Mode::Default) {  // as `describe`: detected unless given
    options.reset_ids =
        reset_ids.is_none() ? detect_vo_resets(kf) : reset_ids.cast<std::vector<int>>();
  }
  SequenceSignatures s;
  {
    py::gil_scoped_release release;
    s = describe_sequence(kf, pts, options);
  }
  return {places_of(s.signatures, s.keyframe_ids, s.frames), s.imitate_ms, s.describe_ms};
}

}  // namespace

void bind_describe(py::module_& m) {
  py::class_<DescribedSequence> seq(m, "SequenceSignatures",
                                    "Signatures of a VO sequence: one per described keyframe.");
  bind_places<DescribedSequence>(seq);
  seq.def_readonly("imitate_ms", &DescribedSequence::imitate_ms,
                   "mean ms per described keyframe: crop + filter")
      .def_readonly("describe_ms", &DescribedSequence::describe_ms,
                    "mean ms per described keyframe: the descriptor (one thread's work)")
      .def("__repr__", [](const DescribedSequence& s) {
        const py::list& sigs = s.places.signatures;
        return "<SequenceSignatures: " + std::to_string(py::len(sigs)) + " places, " +
               std::to_string(py::len(sigs) ? sigs[0].cast<py::array>().shape(1) : 0) +
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
