#pragma once
/// \file jit.hpp
/// \brief nhc::jit — the one path from a scene to a running model, in-process: derive, reduce to
/// index 1, generate the header (docs/generated-code.md), compile it into a cached shared object
/// and load it. Used by `nhc simulate`, `nhc report`, the benchmarks, the tests and applications
/// (CMake target nhc::jit; docs/library.md).
///
///   const auto loaded = nhc::jit::build(scene, nhc::ModelKind::chetaev);
///   const nhc::runtime::Model& model = loaded.model();   // valid while `loaded` lives
///   auto run = nhc::runtime::simulate(model, model.default_parameters(), initial, times, options);

#include "nhc/jit/build.hpp"
#include "nhc/jit/compiler.hpp"
