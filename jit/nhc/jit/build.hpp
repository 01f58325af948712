#pragma once
/// \file build.hpp
/// \brief nhc::jit::build: a scene's model derived, reduced, generated, compiled and loaded.

#include <memory>
#include <optional>

#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/jit/compiler.hpp"
#include "nhc/jit/scene_cache.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::jit {

/// How build() makes the model's functions run (docs/interpreter.md).
enum class Backend {
  compiled,     ///< the header compiled by the C++ compiler (cached) and loaded
  interpreted,  ///< the header's instruction list run by the interpreter: no compiler at all
  automatic,    ///< compiled when this build is in the scene cache (compiled before), else interpreted
};
/// "compiled", "interpreted", "auto".
std::string to_string(Backend backend);
/// The backend a name gives (`--backend`), or nullopt.
std::optional<Backend> parse_backend(const std::string& name);

struct BuildOptions {
  /// The backend; compiled by default for programs, automatic for the command line.
  Backend backend = Backend::compiled;
  /// Backend::automatic: seconds of an interpreted run after which its model is compiled behind
  /// it (compile_behind.hpp); none: predicted_compile_seconds() of its header.
  std::optional<double> compile_behind_after;
  /// The Jacobian to generate; none given: default_jacobian_kind() of the system's size.
  std::optional<JacobianKind> jacobian;
  /// Also dF/dp and dg/dp (HeaderOptions::sensitivities), for runtime::SensitivityIntegrator.
  bool sensitivities = false;
  /// Also the discrete Lagrange–d'Alembert step (HeaderOptions::variational), for
  /// runtime::simulate_variational.
  bool variational = false;
  /// HeaderOptions::split_from_bytes: from this size the header may be compiled as several
  /// translation units (compile.translation_units).
  std::size_t split_from_bytes = HeaderOptions{}.split_from_bytes;
  /// Also the multiplier-free form's mass_matrix, forcing and velocities (HeaderOptions::reduced)
  /// where the model has one. Asked for, not by default: forming it costs more than the rest of
  /// the header on large systems (docs/generated-code.md, "Reduced-form additions").
  bool reduced_form = false;
  /// Reuse the header generated (or, interpreted, the program lowered) for the same scene text,
  /// model and options by an earlier build (scene_cache.hpp): derivation, reduction and generation
  /// are skipped. `NHC_SCENE_CACHE=off`
  /// turns it off too. A scene without source text (SceneSystem::source_text()) is never cached.
  bool scene_cache = true;
  /// The compile cache's directory is also the scene cache's.
  CompileOptions compile;
};

/// Wall time of each stage of build(), in seconds.
struct BuildTimings {
  double derive = 0;       ///< derivation and reduction to index 1 (0 when scene_cached)
  double generate = 0;     ///< code generation (0 when scene_cached)
  double scene_cache = 0;  ///< looking the header up in the scene cache, and storing it after a miss
  double compile = 0;      ///< compiling, or finding the shared object in the cache
  double load = 0;         ///< dlopen and table checks
  /// The header came from the scene cache: nothing was derived, reduced or generated.
  bool scene_cached = false;
  /// The model runs interpreted (Backend): nothing was compiled; compile and load are 0.
  bool interpreted = false;
};

/// A model of a scene, ready to integrate. Owns the loaded library: model() is valid while this
/// object lives. Move-only.
class LoadedModel {
 public:
  LoadedModel(ModelKind kind, JacobianKind jacobian, GeneratedHeader header, CompiledLibrary library,
              runtime::Model model, BuildTimings timings);
  LoadedModel(LoadedModel&&) noexcept = default;
  LoadedModel& operator=(LoadedModel&&) noexcept = default;
  LoadedModel(const LoadedModel&) = delete;
  LoadedModel& operator=(const LoadedModel&) = delete;

  const runtime::Model& model() const noexcept { return model_; }
  ModelKind kind() const noexcept { return kind_; }
  JacobianKind jacobian() const noexcept { return jacobian_; }
  const GeneratedHeader& header() const noexcept { return header_; }
  const CompiledLibrary& library() const noexcept { return library_; }
  const BuildTimings& timings() const noexcept { return timings_; }

 private:
  ModelKind kind_;
  JacobianKind jacobian_;
  GeneratedHeader header_;
  CompiledLibrary library_;
  runtime::Model model_;
  BuildTimings timings_;
};

/// A derivation of a scene's model and the structure of its analysis, made before the build
/// (app::Preparation): the build reduces from them instead of deriving and analysing again.
struct DerivedAndAnalysed {
  const DerivedModel& derived;
  const StructuralAnalysis& structure;
};

/// What build() takes from the scene cache instead of deriving: the header of a model compiled
/// before, or the program of a model interpreted before (docs/interpreter.md).
class SceneCacheHit;

/// build()'s products looked up in the scene cache, once: a caller that decides on whether the
/// build derives (app::prepare_and_build) and the build itself see the same entry, checked once.
struct BuildLookup {
  std::shared_ptr<const SceneCacheHit> hit;  ///< null: the build derives
  double seconds = 0;                        ///< the lookup's wall time
  bool derives() const noexcept { return !hit; }
};

/// Looks up what build(scene, kind, options) may take from the scene cache: the compiled
/// model's header (Backend::compiled; Backend::automatic first), the interpreted model's
/// program (Backend::interpreted; Backend::automatic when the model was not compiled before).
/// An entry that fails a check is removed with a warning and is not a hit.
BuildLookup look_up_build(const Scene& scene, ModelKind kind, const BuildOptions& options = {});

/// Derives `kind` for the scene (MathError when it does not apply), reduces it to index 1,
/// generates the header, compiles it (cached) and loads it. An unchanged scene built before with
/// the same model and options takes its header from the scene cache instead (scene_cache.hpp).
/// Given a derivation and analysis of the same model already made, the model is reduced from its
/// structure (the multiplier-free form from its derivation): neither derived nor analysed again.
LoadedModel build(const Scene& scene, ModelKind kind, const BuildOptions& options = {},
                  const DerivedAndAnalysed* given = nullptr);
/// The same with the scene cache looked up already (look_up_build() of the same arguments).
LoadedModel build(const Scene& scene, ModelKind kind, const BuildOptions& options, const DerivedAndAnalysed* given,
                  const BuildLookup& lookup);

/// Whether build() with these arguments derives the model: false when it takes the header or the
/// interpreted program from the scene cache (look_up_build()). A caller that analyses before a build that derives
/// (app::Preparation) makes the same symbols in the same order on every path, so the generated model does not depend on
/// what its caches hold (GiNaC orders terms by symbol hash, which follows creation order).
bool build_derives(const Scene& scene, ModelKind kind, const BuildOptions& options = {});

/// Records in the scene cache that `header` (built for `scene`, `kind`, `options`) compiled into
/// a library in `library_directory`, as build() does after compiling, so that the next build
/// takes it from there (compile_behind.hpp, after an interpreted run). Nothing when the scene
/// cache is off or the scene has no source text.
void remember_compiled_header(const Scene& scene, ModelKind kind, const BuildOptions& options,
                              const GeneratedHeader& header, JacobianKind jacobian,
                              const std::filesystem::path& library_directory);

/// A header already generated (or written by hand) compiled and loaded.
LoadedModel load_header(const GeneratedHeader& header, ModelKind kind, JacobianKind jacobian,
                        const CompileOptions& options = {});

}  // namespace nhc::jit
