// Database (add, query with every QueryOptions field as a keyword, save, load) and the
// streaming Recognizer.
#include <cmath>
#include <limits>
#include <optional>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/core/pipeline/recognizer.hpp"
#include "loopscan/io/database_file.hpp"

namespace loopscan::python {

namespace {

std::optional<Eigen::Matrix3d> to_frame(const py::object& frame) {
  if (frame.is_none()) return std::nullopt;
  const DoubleArray a = frame.cast<DoubleArray>();
  require_shape(a, "frame", {3, 3}, "the descriptor's axes in the camera frame, rows = axes");
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = a.at(r, c);
  return m;
}

std::optional<Pose3x4> to_pose(const py::object& pose, const std::string& name) {
  if (pose.is_none()) return std::nullopt;
  const DoubleArray a = pose.cast<DoubleArray>();
  require_shape(a, name, {3, 4}, "world-to-camera transform, top three rows");
  Pose3x4 T;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = a.at(r, c);
  return T;
}

PlaceDescriptor descriptor(const DoubleArray& signature, const py::object& frame) {
  PlaceDescriptor d{to_matrix(signature, "signature"), Eigen::Matrix3d::Identity()};
  if (const auto f = to_frame(frame)) d.frame = *f;
  return d;
}

std::string candidate_repr(const Candidate& c) {
  char b[160];
  std::snprintf(b, sizeof b, "<Candidate: session %d keyframe %d, distance %.4f, yaw %.1f deg%s>",
                c.place.session, c.place.keyframe, c.distance, c.yaw_rad * 180.0 / M_PI,
                c.mirrored ? ", mirrored" : "");
  return b;
}

std::vector<Candidate> query(const Database& db, const DoubleArray& signature, int k,
                             const py::object& frame, const std::string& retrieval, int candidates,
                             int index_pool_factor, int stats_sample, int exclude_recent,
                             const std::vector<int>& sessions, double max_distance,
                             double uniqueness_ratio, int distinct_gap, int threads,
                             const py::object& accept) {
  QueryOptions o;
  if (retrieval == "exact")
    o.retrieval = Retrieval::Exact;
  else if (retrieval != "indexed")
    throw py::value_error("retrieval: expected 'indexed' or 'exact', got '" + retrieval + "'");
  o.candidates = candidates;
  o.index_pool_factor = index_pool_factor;
  o.stats_sample = stats_sample;
  o.exclude_recent = exclude_recent;
  o.sessions = sessions;
  o.max_distance = max_distance;
  o.uniqueness_ratio = uniqueness_ratio;
  o.distinct_gap = distinct_gap;
  o.threads = threads;
  if (!accept.is_none()) {
    // A Python rule may raise, which must not happen on a worker thread; it runs with the GIL
    // taken, and is held as a borrowed pointer (the argument outlives the call) so that no
    // copy of the rule is destroyed while the GIL is released.
    if (threads != 1) throw py::value_error("accept: a Python rule needs threads=1");
    if (!PyCallable_Check(accept.ptr())) throw py::type_error("accept: expected a callable");
    PyObject* rule = accept.ptr();
    o.accept = [rule](std::size_t index, const PlaceRef& place) {
      py::gil_scoped_acquire gil;
      return py::reinterpret_borrow<py::function>(rule)(index, place.session, place.keyframe)
          .cast<bool>();
    };
  }
  const PlaceDescriptor d = descriptor(signature, frame);
  py::gil_scoped_release release;
  return db.query(d, k, o);
}

}  // namespace

void bind_database(py::module_& m) {
  py::class_<Candidate>(m, "Candidate", "One place a query matched.")
      .def_property_readonly("session", [](const Candidate& c) { return c.place.session; })
      .def_property_readonly("keyframe", [](const Candidate& c) { return c.place.keyframe; })
      .def_readonly("index", &Candidate::index, "insertion order in the database")
      .def_readonly("distance", &Candidate::distance, "fused z-score (or raw distance)")
      .def_readonly("yaw_rad", &Candidate::yaw_rad,
                    "Scan Context: the place's heading in the query's camera frame; NaN else")
      .def_readonly("mirrored", &Candidate::mirrored)
      .def("__repr__", &candidate_repr);

  py::class_<Database>(m, "Database", "Places to query online (exact or indexed search).")
      .def(py::init(
               [](const std::string& method, const std::string& fusion, double structure_weight) {
                 DatabaseConfig c;
                 c.method = parse_method(method);
                 c.fusion = parse_fusion(fusion);
                 c.structure_weight = structure_weight;
                 return Database(c);
               }),
           py::arg("method") = "sc", py::arg("fusion") = "fused", py::arg("structure_weight") = 2.0)
      .def(
          "add",
          [](Database& db, const DoubleArray& signature, int keyframe, int session,
             const py::object& frame, const py::object& pose) {
            db.add({session, keyframe}, descriptor(signature, frame), to_pose(pose, "pose"));
          },
          py::arg("signature"), py::arg("keyframe"), py::arg("session") = 0,
          py::arg("frame") = py::none(), py::arg("pose") = py::none(),
          "Adds a place: its signature (rows, values), optional descriptor frame (3, 3) and "
          "world-to-camera pose (3, 4).")
      .def("query", &query, py::arg("signature"), py::arg("k") = 1, py::arg("frame") = py::none(),
           py::arg("retrieval") = "indexed", py::arg("candidates") = 50,
           py::arg("index_pool_factor") = 8, py::arg("stats_sample") = 64,
           py::arg("exclude_recent") = 0, py::arg("sessions") = std::vector<int>{},
           py::arg("max_distance") = std::numeric_limits<double>::infinity(),
           py::arg("uniqueness_ratio") = 1.0, py::arg("distinct_gap") = 50, py::arg("threads") = 1,
           py::arg("accept") = py::none(),
           "Up to k places, best first (QueryOptions as keywords; accept(index, session, "
           "keyframe) -> bool: which places may match).")
      .def(
          "save", [](const Database& db, const std::string& path) { io::save_database(db, path); },
          py::arg("path"))
      .def_static(
          "load", [](const std::string& path) { return io::load_database(path); }, py::arg("path"))
      .def("__len__", &Database::size)
      .def_property_readonly("memory_bytes", &Database::memory_bytes)
      .def_property_readonly("method",
                             [](const Database& db) { return method_name(db.config().method); })
      .def("__repr__", [](const Database& db) {
        return "<Database: " + method_name(db.config().method) + ", " + std::to_string(db.size()) +
               " places>";
      });

  py::class_<KeyframeResult>(m, "KeyframeResult", "A place described now, and its matches.")
      .def_readonly("keyframe", &KeyframeResult::keyframe)
      .def_readonly("matches", &KeyframeResult::matches)
      .def("__repr__", [](const KeyframeResult& r) {
        return "<KeyframeResult: keyframe " + std::to_string(r.keyframe) + ", " +
               (r.matches.empty() ? std::string("no match")
                                  : "best " + candidate_repr(r.matches.front())) +
               ">";
      });

  py::class_<Recognizer>(m, "Recognizer",
                         "Streaming place recognition: feed keyframes and their VO points.")
      .def(py::init([](const std::string& method, const std::string& mode, double range_m, int k,
                       int session, int exclude_recent) {
             RecognizerConfig c =
                 RecognizerConfig::make(parse_method(method), parse_mode(mode), range_m);
             c.k = k;
             c.session = session;
             c.query.exclude_recent = exclude_recent;
             return Recognizer(c);
           }),
           py::arg("method") = "sc", py::arg("mode") = "default", py::arg("range_m") = 45.0,
           py::arg("k") = 1, py::arg("session") = 0, py::arg("exclude_recent") = 99)
      .def(
          "add_keyframe",
          [](Recognizer& r, int keyframe, const DoubleArray& T_cam_world, const DoubleArray& points,
             bool reset) {
            const KeyframePose kf = keyframe_pose(keyframe, T_cam_world);
            const std::vector<IdPoint> pts = keyframe_points(keyframe, points);
            py::gil_scoped_release release;
            return r.add_keyframe(kf, pts.data(), pts.size(), reset);
          },
          py::arg("keyframe"), py::arg("T_cam_world"), py::arg("points"), py::arg("reset") = false,
          "One keyframe: its id, world-to-camera pose (3, 4) and the points (N, 4) the VO "
          "exported with it (world frame, x y z gray). Returns the places described now.")
      .def("finish", &Recognizer::finish, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly(
          "database", [](Recognizer& r) -> Database& { return r.database(); },
          py::return_value_policy::reference_internal);
}

}  // namespace loopscan::python
