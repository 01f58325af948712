#pragma once
/// \file scene_bindings.hpp
/// \brief nhc.Scene's C++ side: loading a scene, deriving and analysing its models (the work of
/// `nhc derive` and `nhc analyze`, from the same library functions), with the GIL released
/// while GiNaC works.

#include <pybind11/pybind11.h>

namespace nhc::python {

void register_scene(pybind11::module_& module);

}  // namespace nhc::python
