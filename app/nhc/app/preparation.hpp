#pragma once
/// \file preparation.hpp
/// \brief A run's preparation, shared by both front ends: the scene's model derived and analysed once, the
/// analysis handed on to the build (jit::build reduces from its structure), and the initial-point
/// check the command line and Python make before anything is compiled.

#include <optional>
#include <string>
#include <vector>

#include "nhc/analysis/model_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/jit/build.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// One model of one scene, derived and analysed at most once. `scene` is the scene with the
/// run's parameter values and tolerances (the analysis evaluates at its initial point); the
/// derivation and the structure do not depend on those values, so the build of the scene as
/// written may reduce from them.
class Preparation {
 public:
  Preparation(Scene scene, ModelKind kind) : scene_(std::move(scene)), kind_(kind) {}

  const Scene& scene() const noexcept { return scene_; }
  ModelKind kind() const noexcept { return kind_; }
  /// The analysis (derives first); made once, with the options of the first call.
  const ModelAnalysis& analysis(const InitializationOptions& options);
  /// The structure of the analysis when one was made and found nonsingular, else null: what
  /// jit::build reduces from.
  const StructuralAnalysis* structure() const noexcept;
  /// Builds the model of `scene` (the scene as written: its values are the model's defaults),
  /// from the analysis when one was made.
  jit::LoadedModel build(const Scene& scene, const jit::BuildOptions& options) const;
  /// The same with the scene cache looked up already (jit::look_up_build() of `scene`, `options`).
  jit::LoadedModel build(const Scene& scene, const jit::BuildOptions& options, const jit::BuildLookup& lookup) const;

 private:
  Scene scene_;
  ModelKind kind_;
  std::optional<DerivedModel> derived_;
  std::optional<ModelAnalysis> analysis_;
};

/// The initial-point check's outcome in the scene cache (nhc/jit/scene_cache.hpp): whether a run
/// with the same scene, overrides, tolerances, model and --repair-initial passed it before.
struct InitialPointCheck {
  std::optional<std::string> key;  ///< none: the scene cache is off, or the scene has no text
  bool cached = false;
  /// What the analysis found wrong at t0 that does not stop the run before it starts (a system
  /// Jacobian singular there): the words for a run that then fails at t0.
  std::vector<std::string> problems_at_t0;
};

/// Given initial values that miss a hidden constraint: the analysis' words (the same rule as
/// the runtime, initial_point.hpp), before anything is compiled or written. A check passed
/// before (in the scene cache) is not repeated: an unchanged run derives and analyses nothing.
/// The preparation's scene carries the run's tolerances (its [simulate] rtol and atol).
InitialPointCheck check_initial_point(Preparation& preparation, bool repair);

/// A passed check stored once the model is built, beside its library: a refused or interrupted
/// run leaves no entry.
void remember_check(const InitialPointCheck& check, const jit::LoadedModel& built);

/// A run's model and the check it passed.
struct PreparedModel {
  InitialPointCheck check;
  double check_seconds = 0;  ///< the time the check took (deriving and analysing, when it was made)
  jit::LoadedModel built;
};

/// The one path of nhc simulate and Python's Scene.build to a model: the initial-point check of
/// `preparation` (check_initial_point; none for a scene with a sliding contact, whose violated
/// rolling constraints start it sliding, switched_run.hpp), then the build of `written` (the scene
/// as written, whose values are the model's defaults) from the check's analysis, then the passed
/// check remembered. Refused initial values throw before anything is compiled. A check found cached
/// is not repeated, but a build that derives is still preceded by the analysis: the model is the
/// same whatever the caches hold.
PreparedModel prepare_and_build(Preparation& preparation, const Scene& written, bool repair,
                                const jit::BuildOptions& options);

}  // namespace nhc::app
