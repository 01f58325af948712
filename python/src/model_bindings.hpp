#pragma once
/// \file model_bindings.hpp
/// \brief nhc.Model's C++ side: a scene's model built (nhc::jit: derived, compiled, both caches,
/// loaded) and run (nhc::runtime), its runs as numpy arrays, its residual and Jacobian for the
/// caller's own solvers; and nhc.Scene.linearize (nhc::linearize). The GIL is released while
/// nhc compiles and integrates.

#include <pybind11/pybind11.h>

namespace nhc::python {

void register_model(pybind11::module_& module);

}  // namespace nhc::python
