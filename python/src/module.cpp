// _nhc: the C++ side of the Python package nhc (python/nhc/__init__.py shapes it; docs/python.md).
#include <pybind11/pybind11.h>

#include "error_translation.hpp"
#include "model_bindings.hpp"
#include "optimize_bindings.hpp"
#include "scene_bindings.hpp"

PYBIND11_MODULE(_nhc, m) {
  m.doc() = "nhc, the nonholonomic compiler: C++ bindings (use the package nhc)";
  m.attr("__version__") = NHC_VERSION;
  nhc::python::register_errors(m);
  nhc::python::register_scene(m);
  nhc::python::register_model(m);
  nhc::python::register_optimize(m);
}
