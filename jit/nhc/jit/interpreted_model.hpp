#pragma once
/// \file interpreted_model.hpp
/// \brief A model run without a compiler: each function of its header (residual, Jacobian,
/// hidden constraints, invariants, inputs, …) evaluated by an EvaluationProgram of the same
/// instruction list the header is printed from, behind the same C table (docs/interpreter.md).

#include "nhc/analysis/index1_system.hpp"
#include "nhc/emit/model_preparation.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::jit {

/// Interpreted models that can exist at once in a process (each takes one set of the table's
/// entry points, which C function pointers cannot parametrize otherwise).
inline constexpr int kInterpretedModelSlots = 32;

/// True when every function of `model` has a field of the table the interpreter fills; a model
/// with another function must be compiled.
bool interpretable(const PreparedModel& model);

/// `model` (prepared for `system` of `scene`) as a runtime model whose table calls the
/// interpreter; the model keeps what it needs. Throws EnvironmentError when
/// kInterpretedModelSlots interpreted models exist already, MathError when not interpretable().
runtime::Model interpret(const Scene& scene, const Index1System& system, const PreparedModel& model);

/// Switches an interpreted model to `compiled` (the same header, compiled and loaded): the
/// function entries of `interpreted`'s table become the compiled functions, which give the same
/// numbers to rounding, and the interpreted model keeps `compiled` alive. Call it from the only
/// thread running the model, between calls. False (nothing changed) when `interpreted` is not an
/// interpreted model or the two tables differ in their sizes.
bool adopt_compiled(const runtime::Model& interpreted, const runtime::Model& compiled);

}  // namespace nhc::jit
