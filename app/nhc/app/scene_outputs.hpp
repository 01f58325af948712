#pragma once
/// \file scene_outputs.hpp
/// \brief The scene's [outputs] (named expressions of t, parameters, coordinates, their
/// derivatives and the multipliers) evaluated on the samples of a run, as extra CSV columns of
/// `nhc simulate`. They are not invariants: nothing checks them for drift.

#include "nhc/app/contact_forces.hpp"
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/app/sample_expressions.hpp"

namespace nhc::app {

class SceneOutputs {
 public:
  /// Binds each output to the model's solution with the parameter values `p` (the model's
  /// order). An output that uses a quantity the model does not compute (a multiplier of the
  /// suslov model, x''' of a second-order system) is left out, with a line in notes(); a
  /// `required` one is an InputError at the output's expression.
  SceneOutputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p);

  /// One line per [outputs] or [invariants] entry this model leaves out ("note: …").
  const std::vector<std::string>& notes() const noexcept { return notes_; }
  /// The contacts' forces ([contacts]), whose columns names() and evaluate() end with.
  const ContactForces& contacts() const noexcept { return contacts_; }
  ContactForces& contacts() noexcept { return contacts_; }

  bool empty() const noexcept { return names_.empty(); }
  /// The column names, in the order of [outputs] in the scene file, then the contacts' force
  /// columns (contact_forces.hpp).
  const std::vector<std::string>& names() const noexcept { return names_; }
  /// The outputs at one sample; NaN where an expression is not a finite real number there
  /// (sqrt of a negative number, a division by zero).
  std::vector<double> evaluate(const runtime::Sample& sample) const;

 private:
  std::vector<std::string> names_;
  std::vector<std::string> notes_;
  app::SampleExpressions expressions_;
  ContactForces contacts_;
};

}  // namespace nhc::app
