// The loop closer: verified loops with their relative pose (4x4) and corrected poses.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "configuration.hpp"
#include "loopscan/closure/background_closer.hpp"
#include "loopscan/closure/loop_closer.hpp"

namespace loopscan::python {

namespace {

closure::LoopCloserConfig closer_config(const std::optional<std::string>& method,
                                        const std::optional<std::string>& mode,
                                        const std::optional<double>& range_m,
                                        const std::optional<std::string>& config,
                                        const std::optional<int>& threads) {
  closure::LoopCloserConfig out;
  if (!config) {
    out = closure::LoopCloserConfig::make(parse_method(method.value_or("sc")),
                                          parse_mode(mode.value_or("default")),
                                          range_m.value_or(45.0));
  } else {
    const Configuration c = load_python_configuration(*config, method, mode, range_m);
    validate_loop_closing(c);
    out = loop_closer_config(c);
  }
  // Else the file's closure.threads, or 1; the closer refuses a bad count (a ValueError).
  if (threads) out.threads = *threads;
  return out;
}

closure::BackgroundConfig::WhenFull parse_when_full(const std::string& name) {
  if (name == "skip") return closure::BackgroundConfig::WhenFull::SkipVerification;
  if (name == "wait") return closure::BackgroundConfig::WhenFull::Wait;
  throw py::value_error("when_full: expected 'skip' or 'wait', got '" + name + "'");
}

}  // namespace

void bind_closure(py::module_& m) {
  using closure::KeyframeClosure;
  using closure::Loop;
  using closure::LoopCloser;
  py::class_<Loop>(m, "Loop", "A verified loop candidate and its verdict.")
      .def_readonly("query", &Loop::query, "the query keyframe")
      .def_property_readonly("match_keyframe", [](const Loop& l) { return l.match.keyframe; })
      .def_property_readonly("match_session", [](const Loop& l) { return l.match.session; })
      .def_property_readonly(
          "T_query_match", [](const Loop& l) { return from_isometry(l.T_query_match); },
          "4x4: maps the match's camera frame into the query's (p_query = T @ p_match)")
      .def_readonly("overlap", &Loop::overlap)
      .def_readonly("rmse_m", &Loop::rmse_m)
      .def_property_readonly("verdict", [](const Loop& l) { return closure::to_string(l.verdict); })
      .def_property_readonly("accepted", &Loop::accepted)
      .def("__repr__", [](const Loop& l) {
        char b[160];
        std::snprintf(b, sizeof b, "<Loop: keyframe %d -> %d, %s, overlap %.2f, rmse %.3f m>",
                      l.query, l.match.keyframe, closure::to_string(l.verdict), l.overlap,
                      l.rmse_m);
        return std::string(b);
      });
  py::class_<KeyframeClosure>(m, "KeyframeClosure", "What one keyframe brought.")
      .def_readonly("keyframe", &KeyframeClosure::keyframe)
      .def_readonly("described", &KeyframeClosure::described)
      .def_readonly("candidates", &KeyframeClosure::candidates)
      .def_readonly("verified", &KeyframeClosure::verified)
      .def_readonly("accepted", &KeyframeClosure::accepted)
      .def_readonly("linked_place", &KeyframeClosure::linked_place,
                    "database index of the held place this keyframe linked to (-1: it joined)")
      .def_readonly("skipped", &KeyframeClosure::skipped,
                    "described but left unverified: a background worker was too far behind");
  py::class_<LoopCloser>(m, "LoopCloser",
                         "Online loop closing: recognition, ICP verification, pose graph.")
      .def(py::init([](const std::optional<std::string>& method,
                       const std::optional<std::string>& mode, const std::optional<double>& range_m,
                       const std::optional<std::string>& config, const std::optional<int>& threads) {
             return LoopCloser(closer_config(method, mode, range_m, config, threads));
           }),
           py::arg("method") = py::none(), py::arg("mode") = py::none(),
           py::arg("range_m") = py::none(), py::arg("config") = py::none(),
           py::arg("threads") = py::none(),
           "As Recognizer: method (default sc), mode, range_m (default 45), or a configuration "
           "file (the CLI's --config) with its closure section; threads (default: the file's "
           "closure.threads, else 1) split each candidate's alignments (the same loops).")
      .def("add_keyframe", &add_keyframe_arrays<LoopCloser>, py::arg("keyframe"),
           py::arg("T_cam_world"), py::arg("points"), py::arg("reset") = false)
      .def("finish",
           [](LoopCloser& c) {
             py::gil_scoped_release release;
             c.finish();
           })
      .def(
          "corrected_poses", [](const LoopCloser& c) { return from_poses(c.corrected_poses()); },
          "(ids (K,), T_cam_world (K, 3, 4)) of every keyframe so far, after the pose graph")
      .def_property_readonly("loops", &LoopCloser::loops, "every verification, in order");
  using closure::BackgroundLoopCloser;
  py::class_<BackgroundLoopCloser>(
      m, "BackgroundLoopCloser",
      "LoopCloser with verification and graph solves on a worker thread: add_keyframe returns "
      "after the description and the query; poll() hands over what the worker completed.")
      .def(py::init([](const std::optional<std::string>& method,
                       const std::optional<std::string>& mode, const std::optional<double>& range_m,
                       const std::optional<std::string>& config, int queue_capacity,
                       const std::string& when_full, const std::optional<int>& threads) {
             closure::BackgroundConfig background;
             background.queue_capacity = queue_capacity;
             background.when_full = parse_when_full(when_full);
             return std::make_unique<BackgroundLoopCloser>(
                 closer_config(method, mode, range_m, config, threads), background);
           }),
           py::arg("method") = py::none(), py::arg("mode") = py::none(),
           py::arg("range_m") = py::none(), py::arg("config") = py::none(),
           py::arg("queue_capacity") = 32, py::arg("when_full") = "skip",
           py::arg("threads") = py::none(),
           "As LoopCloser, plus the queue: when it is full, 'skip' leaves the oldest waiting "
           "keyframe unverified (it still joins the graph), 'wait' blocks add_keyframe.")
      .def("add_keyframe", &add_keyframe_arrays<BackgroundLoopCloser>, py::arg("keyframe"),
           py::arg("T_cam_world"), py::arg("points"), py::arg("reset") = false,
           "the description and query; verification follows on the worker (poll)")
      .def("poll", &BackgroundLoopCloser::poll, py::call_guard<py::gil_scoped_release>(),
           "closures completed since the last poll, in input order")
      .def("wait", &BackgroundLoopCloser::wait, py::call_guard<py::gil_scoped_release>(),
           "until the worker has integrated every queued keyframe")
      .def("finish",
           [](BackgroundLoopCloser& c) {
             py::gil_scoped_release release;
             c.finish();
           })
      .def(
          "corrected_poses",
          [](const BackgroundLoopCloser& c) {
            std::vector<KeyframePose> poses;
            {
              py::gil_scoped_release release;
              poses = c.corrected_poses();
            }
            return from_poses(poses);
          },
          "(ids, T_cam_world) of every keyframe given so far: the waiting ones continued by their "
          "odometry from the latest estimate")
      .def_property_readonly(
          "queue",
          [](const BackgroundLoopCloser& c) {
            const closure::QueueStats q = c.queue();
            py::dict d;
            d["waiting"] = q.waiting;
            d["holding_places"] = q.holding_places;
            d["waits"] = q.waits;
            d["waited_ms"] = q.waited_ms;
            d["skipped"] = q.skipped;
            d["dropped_closures"] = q.dropped_closures;
            return d;
          },
          "the worker's queue: waiting, holding_places, waits, waited_ms, skipped, "
          "dropped_closures")
      .def_property_readonly("loops", &BackgroundLoopCloser::loops,
                             "every verification so far, in order");
}

}  // namespace loopscan::python
