// loopscan._loopscan: the C++ library for Python. Arrays in and out (float64 / int32), errors
// as Python exceptions with the C++ message, the GIL released while the library works.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace loopscan::python {
void bind_describe(py::module_& m);
void bind_io(py::module_& m);
void bind_evaluate(py::module_& m);
void bind_database(py::module_& m);
void bind_metrics(py::module_& m);
void bind_closure(py::module_& m);
void bind_vo(py::module_& m);
}  // namespace loopscan::python

PYBIND11_MODULE(_loopscan, m) {
  m.doc() = "loopscan: place recognition for stereo visual odometry (C++ core)";
  m.attr("__version__") = LOOPSCAN_VERSION;
  loopscan::python::bind_describe(m);
  loopscan::python::bind_io(m);
  loopscan::python::bind_evaluate(m);
  loopscan::python::bind_database(m);
  loopscan::python::bind_metrics(m);
  loopscan::python::bind_closure(m);
  loopscan::python::bind_vo(m);
}
