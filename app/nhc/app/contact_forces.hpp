#pragma once
/// \file contact_forces.hpp
/// \brief The scene's [contacts] along a run: each contact's normal force, tangential force and
/// friction ratio from the multipliers (docs/contacts.md: with the rolling constraints written as
/// the components of the contact point's slip velocity, the multipliers are the tangential
/// force's components), as CSV columns NAME.normal, NAME.tangential, NAME.ratio, NAME.state, and
/// the slip of a contact (|F_t| reaching mu F_n) as an event located by IDA's root finding.

#include <optional>
#include <string>
#include <vector>

#include "nhc/app/sample_expressions.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// |F_t| = sqrt(Σ λ_k²) over the contact's rolling constraints k (docs/contacts.md, eq. (3)).
GiNaC::ex tangential_force(const Scene& scene, const SceneContact& contact);

/// The event NAME.slip of a contact: mu F_n - |F_t| falling through zero, or below zero at t0.
SceneEvent slip_event(const Scene& scene, const SceneContact& contact);

/// The slip events of the contacts whose on_slip is "stop" (they end the run), in file order.
std::vector<SceneEvent> slip_events(const Scene& scene);

class ContactForces {
 public:
  /// Binds each contact to the model's solution with the parameter values `p` (the model's
  /// order). A contact whose forces use a quantity the model does not compute (the suslov
  /// model has no multipliers) is left out, with a line in notes().
  ContactForces(const Scene& scene, const runtime::Model& model, const std::vector<double>& p);

  const std::vector<std::string>& notes() const noexcept { return notes_; }
  /// NAME.normal, NAME.tangential, NAME.ratio, NAME.state for each contact kept, in file order.
  const std::vector<std::string>& names() const noexcept { return names_; }
  /// The columns at one sample: F_n, |F_t|, |F_t|/F_n and the state (1 rolling).
  std::vector<double> evaluate(const runtime::Sample& sample) const;

  /// The contact `name` slides over `spans` (switched_run.hpp): its state column is 0 there.
  void set_sliding(const std::string& name, std::vector<std::pair<double, double>> spans, bool first_closed);

  /// "contact NAME slips at t = T (needs mu >= X)" for the hit of a slip event, X the friction
  /// ratio at the hit's state; nullopt for any other event.
  std::optional<std::string> slip_line(const runtime::EventHit& hit) const;

  /// Per contact, the friction the motion needs: "contact NAME needs mu >= X (the largest
  /// |F_t|/F_n at the output times, at t = T; mu = M)" over `samples`.
  std::vector<std::string> need_lines(const std::vector<runtime::Sample>& samples) const;

 private:
  struct Kept {
    const SceneContact* contact;
    std::size_t normal;                              ///< index of F_n among the expressions; |F_t| follows it
    std::vector<std::pair<double, double>> sliding;  ///< (from, to] spans of sliding
    bool first_closed = false;                       ///< the first span is [from, to]
  };
  std::vector<Kept> kept_;
  std::vector<std::string> names_;
  std::vector<std::string> notes_;
  SampleExpressions expressions_;
};

}  // namespace nhc::app
