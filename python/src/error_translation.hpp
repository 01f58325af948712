#pragma once
/// \file error_translation.hpp
/// \brief nhc's C++ failures as the Python exceptions of nhc/errors.py, with the words of the
/// command line: InputError → nhc.SceneError (.file, .line, .column), MathError and
/// base::SolverError → nhc.MathError (.t when known), EnvironmentError and out of memory →
/// nhc.HostError. Nothing aborts the interpreter.

#include <pybind11/pybind11.h>

namespace nhc::python {

/// Registers the translation; `package` is the imported nhc.errors module.
void register_errors(pybind11::module_& module);

}  // namespace nhc::python
