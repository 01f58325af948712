#pragma once
/// \file switched_run.hpp
/// \brief A contact with on_slip = "slide" (docs/contacts.md, "Sliding"): the sliding model (the
/// scene without the contact's rolling constraints, with Coulomb friction -mu F_n f/|f| on its
/// slip velocity f), and the two models side by side (ContactSwitch): the state carried over at
/// the contact's slip and stick, where the run engine (run_engine.hpp) switches between them.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/app/sample_expressions.hpp"
#include "nhc/jit/build.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The scene's contact with on_slip = "slide", nullptr when none. InputError (at its on_slip)
/// for a second one, or for a normal force that uses a multiplier or an acceleration (the
/// Coulomb force of the sliding model is a force of t, q and q').
const SceneContact* sliding_contact(const Scene& scene);

/// The events of `events` the sliding model evaluates: those that use no multiplier (the rolling
/// constraints' multipliers are the friction force there, the others renumbered).
std::vector<SceneEvent> events_without_multipliers(const Scene& scene, const std::vector<SceneEvent>& events);

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

/// The rolling and the sliding model of one contact side by side: the sliding model's
/// parameters, the states carried over at each switch and the contact's slip velocity f on either
/// model's points (docs/contacts.md, "The switches"). The run engine (run_engine.hpp) switches
/// with it; `scene`, `contact` and both models must outlive it.
class ContactSwitch {
 public:
  ContactSwitch(const Scene& scene, const SceneContact& contact, const runtime::Model& rolling,
                const runtime::Model& sliding, const std::vector<double>& p);

  const runtime::Model& sliding() const noexcept { return *sliding_; }
  /// The sliding model's parameter values: the rolling model's by name, else its defaults.
  const std::vector<double>& sliding_parameters() const noexcept { return ps_; }

  /// A sliding model's point in the rolling model's states: while sliding, the multipliers of the
  /// contact's rolling constraints hold the Coulomb force's components -mu F_n f_k/|f|.
  runtime::Sample to_rolling(const runtime::Sample& s) const;
  /// The rolling model's states with the sliding model's values (the friction components 0):
  /// what a u(t, y) of the rolling model's states reads while the contact slides.
  void rolling_states(const double* sliding_y, std::vector<double>& y) const;
  /// The sliding model's inputs from the rolling model's (by name).
  std::vector<double> sliding_inputs(const std::vector<double>& rolling_u) const;

  /// The sliding model's start at a rolling point: q and q' given, the rest solved.
  runtime::InitialState sliding_start(const runtime::Sample& rolling_point) const;
  /// The rolling model's start at a (rolling-layout) point: the positions pinned, q' repaired
  /// onto the rolling constraints.
  runtime::InitialState rolling_start(const runtime::Sample& rolling_point) const;

  /// f on a rolling model's point, on a sliding model's point.
  std::vector<double> slip_on_rolling(const runtime::Sample& s) const;
  std::vector<double> slip_on_sliding(const runtime::Sample& s) const;
  /// The slip's direction at a slip from rolling: against the friction force the rolling needed,
  /// d = -F_t/|F_t| (F_t: the multipliers of the rolling constraints at `rolling_point`).
  std::vector<double> slip_direction(const runtime::Sample& rolling_point) const;

  /// The event NAME.stick of the sliding model: f.d falls through 1e-6 max(1, |f(start)|), where
  /// IDA's corrector still converges (the Jacobian of the Coulomb force grows as 1/|f|).
  runtime::Event stick_event(const std::vector<double>& direction, const runtime::InitialState& start) const;
  /// Carries a stick hit (the sliding model's state) on along y' to f.d = 0 (the rest of the step
  /// is O(near^2)); the hit's t moves there.
  void carry_to_stick(runtime::EventHit& hit, const std::vector<double>& direction) const;

 private:
  const Scene* scene_;
  const SceneContact* contact_;
  const runtime::Model* rolling_;
  const runtime::Model* sliding_;
  std::vector<double> ps_;
  std::vector<int> from_;      ///< per rolling state: its sliding state index, or -1
  std::vector<int> friction_;  ///< per rolling state: the rolling constraint it is the force of, or -1
  std::vector<int> inputs_;    ///< per sliding input: the rolling input of the same name, or -1
  std::shared_ptr<SampleExpressions> on_rolling_, on_sliding_;  ///< F_n, then f
};

}  // namespace nhc::app
