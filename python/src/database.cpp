// Database (add, query with every QueryOptions field as a keyword, save, load) and the
// streaming Recognizer.
#include <cmath>
#include <limits>
#include <optional>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "configuration.hpp"
#include "loopscan/core/pipeline/recognizer.hpp"
#include "loopscan/io/database_file.hpp"

namespace loopscan::python {

namespace {

PlaceDescriptor descriptor(const DoubleArray& signature, const py::object& frame) {
  PlaceDescriptor d{to_matrix(signature, "signature"), Eigen::Matrix3d::Identity()};
  if (!frame.is_none()) {
    d.frame = to_fixed<3, 3>(frame.cast<DoubleArray>(), "frame",
                             "the descriptor's axes in the camera frame, rows = axes");
  }
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
                             int index_pool_factor, int stats_sample, int refine,
                             int exclude_recent, std::vector<int> sessions, double max_distance,
                             double uniqueness_ratio, int distinct_gap, int threads,
                             const py::object& accept) {
  QueryOptions o;
  o.retrieval = parse_retrieval(retrieval);
  o.candidates = candidates;
  o.index_pool_factor = index_pool_factor;
  o.stats_sample = stats_sample;
  o.refine = refine;
  o.exclude_recent = exclude_recent;
  o.sessions = std::move(sessions);
  o.max_distance = max_distance;
  o.uniqueness_ratio = uniqueness_ratio;
  o.distinct_gap = distinct_gap;
  o.threads = threads;
  const PlaceDescriptor d = descriptor(signature, frame);
  if (!accept.is_none()) {
    // The database asks the rule on the calling thread, before any scoring thread starts: the
    // GIL stays held for this query, and an exception in the rule reaches the caller.
    if (!PyCallable_Check(accept.ptr())) throw py::type_error("accept: expected a callable");
    o.accept = [&accept](std::size_t index, const PlaceRef& place) {
      return accept(index, place.session, place.keyframe).cast<bool>();
    };
    return db.query(d, k, o);
  }
  py::gil_scoped_release release;
  return db.query(d, k, o);
}

}  // namespace

void bind_database(py::module_& m) {
  const QueryOptions kQuery;  // the keyword defaults are the C++ defaults
  py::class_<Candidate>(m, "Candidate", "One place a query matched.")
      .def_property_readonly("session", [](const Candidate& c) { return c.place.session; })
      .def_property_readonly("keyframe", [](const Candidate& c) { return c.place.keyframe; })
      .def_readonly("index", &Candidate::index, "insertion order in the database")
      .def_readonly("distance", &Candidate::distance, "fused z-score (or raw distance)")
      .def_readonly("yaw_rad", &Candidate::yaw_rad,
                    "Scan Context and bev: the place's heading in the query's camera frame; NaN "
                    "else")
      .def_readonly("mirrored", &Candidate::mirrored)
      .def_readonly("x_m", &Candidate::x_m,
                    "bev: the place keyframe's x (right) in the query's camera frame; NaN else")
      .def_readonly("z_m", &Candidate::z_m,
                    "bev: the place keyframe's z (forward) in the query's camera frame; NaN else")
      .def("__repr__", &candidate_repr);

  py::class_<Database>(m, "Database", "Places to query online (exact or indexed search).")
      .def(py::init([](const std::optional<std::string>& method,
                       const std::optional<std::string>& fusion,
                       const std::optional<double>& structure_weight,
                       const std::optional<std::string>& storage,
                       const std::optional<std::string>& config) {
             DatabaseConfig c;
             if (config) {
               c = database_config(
                   load_python_configuration(*config, method, std::nullopt, std::nullopt));
             } else {
               c.method = parse_method(method.value_or("sc"));
             }
             if (fusion) c.fusion = parse_fusion(*fusion);
             if (structure_weight) c.structure_weight = *structure_weight;
             if (storage) c.storage = parse_storage(*storage);
             return Database(c);
           }),
           py::arg("method") = py::none(), py::arg("fusion") = py::none(),
           py::arg("structure_weight") = py::none(), py::arg("storage") = py::none(),
           py::arg("config") = py::none(),
           "method: sc | m2dp | delight | bev (default sc); fusion, structure_weight and storage "
           "default to DatabaseConfig's; config: a configuration file (as the CLI's --config) "
           "whose database and descriptor sections replace those defaults.")
      .def(
          "add",
          [](Database& db, const DoubleArray& signature, int keyframe, int session,
             const py::object& frame, const py::object& pose) {
            std::optional<Pose3x4> T;
            if (!pose.is_none())
              T = to_fixed<3, 4>(pose.cast<DoubleArray>(), "pose",
                                 "world-to-camera transform, top three rows");
            db.add({session, keyframe}, descriptor(signature, frame), T);
          },
          py::arg("signature"), py::arg("keyframe"), py::arg("session") = 0,
          py::arg("frame") = py::none(), py::arg("pose") = py::none(),
          "Adds a place: its signature (rows, values), optional descriptor frame (3, 3) and "
          "world-to-camera pose (3, 4).")
      .def("query", &query, py::arg("signature"), py::arg("k") = 1, py::arg("frame") = py::none(),
           py::arg("retrieval") = retrieval_name(kQuery.retrieval),
           py::arg("candidates") = kQuery.candidates,
           py::arg("index_pool_factor") = kQuery.index_pool_factor,
           py::arg("stats_sample") = kQuery.stats_sample, py::arg("refine") = kQuery.refine,
           py::arg("exclude_recent") = kQuery.exclude_recent, py::arg("sessions") = kQuery.sessions,
           py::arg("max_distance") = kQuery.max_distance,
           py::arg("uniqueness_ratio") = kQuery.uniqueness_ratio,
           py::arg("distinct_gap") = kQuery.distinct_gap, py::arg("threads") = kQuery.threads,
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
      .def(py::init([](const std::optional<std::string>& method,
                       const std::optional<std::string>& mode, const std::optional<double>& range_m,
                       int k, int session, int exclude_recent,
                       const std::optional<std::string>& config) {
             RecognizerConfig c =
                 config
                     ? recognizer_config(load_python_configuration(*config, method, mode, range_m))
                     : RecognizerConfig::make(parse_method(method.value_or("sc")),
                                              parse_mode(mode.value_or("default")),
                                              range_m.value_or(45.0));
             c.k = k;
             c.session = session;
             c.query.exclude_recent = exclude_recent;
             return Recognizer(c);
           }),
           py::arg("method") = py::none(), py::arg("mode") = py::none(),
           py::arg("range_m") = py::none(), py::arg("k") = 1, py::arg("session") = 0,
           py::arg("exclude_recent") =
               RecognizerConfig::make(Method::ScanContext).query.exclude_recent,
           py::arg("config") = py::none(),
           "method: sc | m2dp | delight | bev (default sc), mode: default | reference, range_m "
           "(default 45); config: a configuration file (as the CLI's --config) whose values "
           "replace the defaults of its method and mode, range_m on top when given.")
      .def("add_keyframe", &add_keyframe_arrays<Recognizer>, py::arg("keyframe"),
           py::arg("T_cam_world"), py::arg("points"), py::arg("reset") = false,
           "One keyframe: its id, world-to-camera pose (3, 4) and the points (N, 4) the VO "
           "exported with it (world frame, x y z gray). Returns the places described now.")
      .def("finish", &Recognizer::finish, py::call_guard<py::gil_scoped_release>())
      .def_property_readonly(
          "database", [](Recognizer& r) -> Database& { return r.database(); },
          py::return_value_policy::reference_internal);
}

}  // namespace loopscan::python
