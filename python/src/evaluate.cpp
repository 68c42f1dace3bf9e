// evaluate_places: the paper's evaluation, as `loopscan evaluate` computes it.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "loopscan/eval/place_evaluation.hpp"

namespace loopscan::python {

namespace {

// Each one (rows, the method's width), as `evaluate` reads them from signatures.txt.
std::vector<Signature> to_signatures(const py::list& list, const std::string& name, Method method) {
  std::vector<Signature> out;
  out.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    const DoubleArray a = list[i].cast<DoubleArray>();
    const std::string item = name + "[" + std::to_string(i) + "]";
    require_shape(a, item, {-1, signature_columns(method)},
                  "a " + method_name(method) + " signature: rows x its width");
    out.push_back(to_matrix(a, item));
  }
  return out;
}

eval::PlaceEvaluation evaluate(const py::list& queries, const py::list& database,
                               const DoubleArray& query_positions,
                               const DoubleArray& database_positions, const std::string& method,
                               const std::string& mode, const std::string& fusion,
                               const std::string& protocol, double threshold_m, int mask,
                               double structure_weight, int threads) {
  const Method met = parse_method(method);
  const std::vector<Signature> q = to_signatures(queries, "queries", met);
  const std::vector<Signature> db = to_signatures(database, "database", met);
  const std::vector<Eigen::Vector3d> qp = to_positions(query_positions, "query_positions");
  const std::vector<Eigen::Vector3d> dp = to_positions(database_positions, "database_positions");
  if (qp.size() != q.size() || dp.size() != db.size())
    throw py::value_error("positions: expected one per signature (queries " +
                          std::to_string(q.size()) + ", positions " + std::to_string(qp.size()) +
                          "; database " + std::to_string(db.size()) + ", positions " +
                          std::to_string(dp.size()) + ")");
  eval::PlaceEvaluationOptions o = eval::PlaceEvaluationOptions::make(met, parse_mode(mode));
  if (!fusion.empty()) o.fusion = parse_fusion(fusion);
  o.structure_weight = structure_weight;
  if (protocol == "same")
    o.protocol = eval::same_session_protocol();
  else if (protocol == "cross")
    o.protocol = eval::cross_session_protocol();
  else
    throw py::value_error(
        "protocol: expected 'same' (10 m, mask 100) or 'cross' (25 m, no "
        "mask), got '" +
        protocol + "'");
  if (threshold_m > 0) o.protocol.threshold_m = threshold_m;
  if (mask >= 0) o.protocol.mask_width = mask;
  o.threads = threads;
  py::gil_scoped_release release;
  return eval::evaluate_places(q, db, qp, dp, o);
}

}  // namespace

void bind_evaluate(py::module_& m) {
  using PE = eval::PlaceEvaluation;
  py::class_<PE>(m, "PlaceEvaluation", "Precision-recall of one query set against a map.")
      .def_property_readonly("auc", [](const PE& e) { return e.pr.auc; })
      .def_property_readonly("recall_at_100_precision",
                             [](const PE& e) { return e.pr.recall_at_100_precision; })
      .def_property_readonly("f1_max", [](const PE& e) { return e.pr.f1_max; })
      .def_property_readonly("n_gt_loops", [](const PE& e) { return e.pr.n_gt_loops; })
      .def_property_readonly("n_queries", [](const PE& e) { return e.pr.n_queries; })
      .def_property_readonly(
          "precision",
          [](const PE& e) {
            py::array_t<double> a(static_cast<py::ssize_t>(e.pr.curve.size()));
            for (std::size_t i = 0; i < e.pr.curve.size(); ++i)
              a.mutable_at(i) = e.pr.curve[i].precision;
            return a;
          },
          "the PR curve's precision, one point per ranked query")
      .def_property_readonly("recall",
                             [](const PE& e) {
                               py::array_t<double> a(static_cast<py::ssize_t>(e.pr.curve.size()));
                               for (std::size_t i = 0; i < e.pr.curve.size(); ++i)
                                 a.mutable_at(i) = e.pr.curve[i].recall;
                               return a;
                             })
      .def_property_readonly(
          "matches",
          [](const PE& e) {
            py::array_t<int> a(static_cast<py::ssize_t>(e.matches.size()));
            for (std::size_t i = 0; i < e.matches.size(); ++i) a.mutable_at(i) = e.matches[i].match;
            return a;
          },
          "int (Q,): the database index each query matched best")
      .def_property_readonly(
          "distances",
          [](const PE& e) {
            py::array_t<double> a(static_cast<py::ssize_t>(e.matches.size()));
            for (std::size_t i = 0; i < e.matches.size(); ++i)
              a.mutable_at(i) = e.matches[i].distance;
            return a;
          },
          "float (Q,): the fused distance of that match")
      .def_readonly("query_ms", &PE::query_ms)
      .def("__repr__", [](const PE& e) {
        char b[160];
        std::snprintf(b, sizeof b,
                      "<PlaceEvaluation: AUC %.4f, recall@100%%P %.4f, F1-max %.4f, %d GT loops / "
                      "%d queries>",
                      e.pr.auc, e.pr.recall_at_100_precision, e.pr.f1_max, e.pr.n_gt_loops,
                      e.pr.n_queries);
        return std::string(b);
      });
  m.def("evaluate_places", &evaluate, py::arg("queries"), py::arg("database"),
        py::arg("query_positions"), py::arg("database_positions"), py::arg("method") = "sc",
        py::arg("mode") = "default", py::arg("fusion") = "", py::arg("protocol") = "same",
        py::arg("threshold_m") = 0.0, py::arg("mask") = -1, py::arg("structure_weight") = 2.0,
        py::arg("threads") = 1,
        "The paper's evaluation, as `loopscan evaluate`: signatures (lists of (rows, values) "
        "arrays) and positions ((N, 3) arrays). fusion '' = the mode's default (adaptive / "
        "fused); protocol 'same' (10 m, mask 100) or 'cross' (25 m, no mask); threshold_m > 0 "
        "and mask >= 0 override the protocol's.");
}

}  // namespace loopscan::python
