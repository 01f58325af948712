#pragma once
/// \file optimize_bindings.hpp
/// \brief nhc.Scene.optimize's C++ side (nhc::optimize): the scene's [optimize] problem
/// transcribed and solved by IPOPT, the path as columns and data, the cost, the violation, the
/// iterations and IPOPT's status in words. The GIL is held (IPOPT calls back into the
/// transcription, whose problem holds GiNaC expressions); Ctrl-C stops it between iterations.

#include <pybind11/pybind11.h>

namespace nhc::python {

void register_optimize(pybind11::module_& module);

}  // namespace nhc::python
