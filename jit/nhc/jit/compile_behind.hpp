#pragma once
/// \file compile_behind.hpp
/// \brief The compiler behind an interpreted run (Backend::automatic, docs/interpreter.md): a
/// run that has lasted as long as its header is predicted to take to compile starts the compile
/// on another thread, switches to the compiled functions when they are ready (the same numbers
/// to rounding), and leaves the library in the caches for the next run. A run shorter than that
/// never compiles: paying for the compiler only once the interpreter has cost as much is at
/// most twice the better of the two choices made in hindsight (the ski-rental argument).

#include <chrono>
#include <future>
#include <optional>

#include "nhc/jit/build.hpp"

namespace nhc::jit {

/// Seconds `header` is predicted to take to compile with `options` on this machine (a fit to
/// measurements, docs/interpreter.md: 0.3 s plus 20 s per MB optimized, or plus 3 s per MB at the
/// -O0 of long headers, optimization_flags()).
double predicted_compile_seconds(const GeneratedHeader& header, const CompileOptions& options = {});

class CompileBehind {
 public:
  /// `loaded`: what build(scene, kind, options) returned; does nothing unless it is interpreted
  /// and options.backend is automatic. `loaded` must outlive this object.
  CompileBehind(const Scene& scene, ModelKind kind, const BuildOptions& options, const LoadedModel& loaded);
  ~CompileBehind();
  CompileBehind(const CompileBehind&) = delete;
  CompileBehind& operator=(const CompileBehind&) = delete;

  /// Between steps of the run, from the thread running the model: starts the compile once the
  /// run has lasted the predicted compile time, switches once it is done. True once switched.
  bool poll();
  /// After the run: waits for a compile that was started and records it for the next run.
  /// A failing compile is a warning (the run itself succeeded). Returns true when compiled.
  bool finish();
  bool started() const noexcept { return compile_.valid() || switched_; }
  bool switched() const noexcept { return switched_; }

 private:
  const Scene& scene_;
  ModelKind kind_;
  BuildOptions options_;
  const LoadedModel& loaded_;
  bool active_ = false;
  bool switched_ = false;
  bool recorded_ = false;
  double predicted_seconds_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::future<std::pair<CompiledLibrary, runtime::Model>> compile_;
  std::optional<std::pair<CompiledLibrary, runtime::Model>> compiled_;
};

}  // namespace nhc::jit
