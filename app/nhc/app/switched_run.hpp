#pragma once
/// \file switched_run.hpp
/// \brief A contact with on_slip = "slide" (docs/contacts.md, "Sliding"): the sliding model (the
/// scene without the contact's rolling constraints, with Coulomb friction -mu F_n f/|f| on its
/// slip velocity f), and the run that switches between the rolling and the sliding model at the
/// contact's slip and stick, the state carried over at each switch.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/jit/build.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The scene's contact with on_slip = "slide", nullptr when none. InputError (at its on_slip)
/// for a second one, or for a normal force that uses a multiplier or an acceleration (the
/// Coulomb force of the sliding model is a force of t, q and q').
const SceneContact* sliding_contact(const Scene& scene);

/// The sliding model's scene: the scene's text without the contact's rolling constraints and
/// with the generalized Coulomb force Q_i = -mu F_n sum_k (f^k/|f|) df^k/dq_i' (docs/contacts.md,
/// eq. (8)) in [forces]; parsed like any scene, so its model is cached like any model.
Scene sliding_scene(const Scene& scene, const SceneContact& contact);

/// The sliding model of `scene` (the scene of the run, after its parameter values) for
/// `contact`: sliding_scene() built as `kind` with `options`, as nhc simulate and Python's
/// simulate integrate it.
jit::LoadedModel build_sliding_model(const Scene& scene, const SceneContact& contact, ModelKind kind,
                                     const jit::BuildOptions& options);

/// A time span the contact slides: (from, to], or [from, to] when the run starts sliding; `to`
/// is +infinity when the run ends sliding.
struct SlidingSpan {
  double from = 0, to = 0;
  bool from_included = false;
};

/// The samples at which the contact rolls (outside every span of `sliding`): where the rolling
/// model's hidden constraints and invariants hold, so a run's drift is measured over them.
std::vector<runtime::Sample> rolling_samples(const std::vector<runtime::Sample>& samples,
                                             const std::vector<SlidingSpan>& sliding);

struct SwitchedRun {
  /// The samples and event hits in the rolling model's states: while sliding, the multipliers
  /// of the contact's rolling constraints hold the friction force's components.
  runtime::RunResult run;
  std::vector<SlidingSpan> sliding;  ///< when the contact slides
  std::vector<std::string> notes;  ///< one line per switch back to rolling that projected q'
};

/// Integrates from `initial` (the rolling model's) through `times`, switching to `sliding` at
/// the event NAME.slip and back at NAME.stick (the slip velocity along its direction at the slip
/// crosses zero); starts sliding when `initial` violates the contact's rolling constraints.
/// `events`: the other events of the run (on the rolling model; on the sliding model those that
/// use no multiplier).
SwitchedRun simulate_switched(const Scene& scene, const SceneContact& contact, const runtime::Model& rolling,
                              const runtime::Model& sliding, const std::vector<double>& p,
                              const runtime::InitialState& initial, const std::vector<double>& times,
                              const runtime::IntegratorOptions& options, const std::vector<SceneEvent>& events,
                              const runtime::InputFunction& inputs);

}  // namespace nhc::app
