#pragma once
/// \file interpreted_model.hpp
/// \brief A model run without a compiler: each function of its header (residual, Jacobian,
/// hidden constraints, invariants, inputs, …) evaluated by an EvaluationProgram of the same
/// instruction list the header is printed from, behind the same C table (docs/interpreter.md).

#include <memory>
#include <string>
#include <string_view>

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

/// What an interpreted model runs: its table's data (sizes, state layout, names, the Jacobian's
/// structure) and one lowered EvaluationProgram per function. Made from a prepared model, or read
/// back from bytes (the scene cache keeps them, so that a second run neither derives nor lowers).
class InterpretedProgram;

/// Lowers every function of `model` (prepared for `system` of `scene`). MathError when not
/// interpretable().
std::shared_ptr<const InterpretedProgram> interpreted_program(const Scene& scene, const Index1System& system,
                                                              const PreparedModel& model);
/// The program as bytes, read back by interpreted_program_from_bytes().
std::string to_bytes(const InterpretedProgram& program);
/// The program `bytes` hold; null when they are not one (malformed, truncated, another layout),
/// or when it is not the model `model` of the scene `scene_name`: such bytes are never run.
std::shared_ptr<const InterpretedProgram> interpreted_program_from_bytes(std::string_view bytes,
                                                                         const std::string& scene_name,
                                                                         const std::string& model);

/// `program` as a runtime model whose table calls the interpreter; the model keeps the program.
/// Throws EnvironmentError when kInterpretedModelSlots interpreted models exist already.
runtime::Model interpret(std::shared_ptr<const InterpretedProgram> program);
/// interpret(interpreted_program(scene, system, model)).
runtime::Model interpret(const Scene& scene, const Index1System& system, const PreparedModel& model);

/// Switches an interpreted model to `compiled` (the same header, compiled and loaded): the
/// function entries of `interpreted`'s table become the compiled functions, which give the same
/// numbers to rounding, and the interpreted model keeps `compiled` alive. Call it from the only
/// thread running the model, between calls. False (nothing changed) when `interpreted` is not an
/// interpreted model or the two tables differ in their sizes.
bool adopt_compiled(const runtime::Model& interpreted, const runtime::Model& compiled);

}  // namespace nhc::jit
