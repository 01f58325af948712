// _nhc: the C++ side of the Python package nhc (python/nhc/__init__.py shapes it; docs/python.md).
#include <pybind11/pybind11.h>

#include "error_translation.hpp"
#include "model_bindings.hpp"
#include "optimize_bindings.hpp"
#include "scene_bindings.hpp"
#include "symbolic_work.hpp"

#include <cmath>
#include <string>

#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/expr/work_stage.hpp"

namespace nhc::python {

double& work_limit_seconds() {
  static double seconds = work_budget::kDefaultWorkSeconds;
  return seconds;
}

}  // namespace nhc::python

PYBIND11_MODULE(_nhc, m) {
  m.doc() = "nhc, the nonholonomic compiler: C++ bindings (use the package nhc)";
  m.attr("__version__") = NHC_VERSION;
  static nhc::python::GilSymbolicLock gil;  // lives as long as the process: the library keeps a pointer
  nhc::set_symbolic_lock(&gil);
  nhc::python::register_errors(m);
  nhc::python::register_scene(m);
  nhc::python::register_model(m);
  nhc::python::register_optimize(m);
  m.def(
      "_set_work_limit",
      [](double seconds) {
        if (!std::isfinite(seconds) || seconds <= 0)
          throw pybind11::value_error("the work limit must be a positive number of seconds, got " +
                                      std::to_string(seconds));
        nhc::python::work_limit_seconds() = seconds;
      },
      pybind11::arg("seconds"),
      "Sets the processor seconds of symbolic work (loading, deriving, analysing, generating) one call\n"
      "may spend before it stops with nhc.SceneError naming the scene and the stage: the command\n"
      "line's --work-limit (default 4 s).");
  m.def(
      "_work_limit", [] { return nhc::python::work_limit_seconds(); },
      "The processor seconds of symbolic work one call may spend (nhc.set_work_limit).");
  // The library's counters of its two costly symbolic steps, for the tests that show a build
  // derives and analyses its model once (app/nhc/app/preparation.hpp).
  m.def("_derive_model_calls", &nhc::derive_model_calls, "How many models this process has derived.");
  m.def("_analyze_structure_calls", &nhc::analyze_structure_calls,
        "How many structural analyses (the Sigma-method) this process has run.");
}
