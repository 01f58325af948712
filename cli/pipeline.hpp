#pragma once
/// \file pipeline.hpp
/// \brief The pieces of the pipeline that the commands integrating a scene share (nhc simulate,
/// nhc report): the model to integrate, generating and compiling its header into a cached shared
/// object, loading it, and the scene's [initial] as the runtime's initial state.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "nhc/emit/header_emitter.hpp"
#include "nhc/io/shell.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start);

// shell_quote() and run_command(): nhc/io/shell.hpp.

/// `$NHC_CACHE_DIR`, else `$XDG_CACHE_HOME/nhc`, else `~/.cache/nhc`.
std::filesystem::path cache_directory();

struct CompiledModel {
  std::string path;     ///< the shared object
  bool reused = false;  ///< found in the cache
};

/// Compiles the generated header into a shared object exporting nhc_model_table_get with the
/// compiler that built nhc (`-std=c++17 -O2 -fPIC -shared`), or reuses the cached one: the key
/// hashes the code, the compiler's path and version, and the flags. Throws std::runtime_error
/// with the compiler's output when it fails.
CompiledModel compile_model(const GeneratedHeader& header);

/// A model of a scene, derived, reduced, generated, compiled and loaded.
struct BuiltModel {
  ModelKind kind = ModelKind::chetaev;
  JacobianKind jacobian = JacobianKind::dense;
  GeneratedHeader header;
  CompiledModel compiled;
  runtime::Model model;
  double derive_seconds = 0;   ///< derivation, reduction, code generation
  double compile_seconds = 0;  ///< compilation (or cache look-up) and loading
};

/// Derives `kind` for the scene (MathError when it does not apply), reduces it to index 1,
/// generates the header with the given Jacobian (none given: dense below 40 states, sparse from
/// 40) and compiles and loads it.
BuiltModel build_model(const Scene& scene, ModelKind kind, std::optional<JacobianKind> jacobian);

/// The scene's [initial] as the runtime's InitialState: `x = [x0, x'0]` gives the states x and x';
/// values beyond the states' orders are y' guesses.
runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model);

/// A number with `precision` significant digits (iostream default notation).
std::string format_number(double v, int precision = 3);

}  // namespace nhc::cli
