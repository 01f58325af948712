#pragma once
/// \file sample_expressions.hpp
/// \brief Expressions of the scene (t, parameters, inputs, coordinates and their derivatives, the
/// multipliers, definitions) evaluated on the samples of a run: the values of [outputs] and of
/// [visual] (cli/scene_outputs.hpp, cli/visual_samples.hpp) and of [events] (scene_events.hpp).

#include <ginac/ginac.h>

#include <memory>
#include <string>
#include <vector>

#include "nhc/expr/numeric_program.hpp"

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

class SampleExpressions {
 public:
  /// Parameters take the model's values `p` (the model's order), and the scene's for one the
  /// model does not read.
  SampleExpressions(const Scene& scene, const runtime::Model& model, const std::vector<double>& p);
  /// With `free` symbols besides the scene's (a sampled controller's states), whose values each
  /// evaluate() is given.
  SampleExpressions(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                    std::vector<GiNaC::ex> free);

  /// Adds e (its definitions substituted); its value is evaluate()'s entry number size() - 1.
  /// When the model does not compute a quantity e uses (a multiplier of the suslov model,
  /// x''' of a second-order system), e is not added and that quantity is returned in scene
  /// notation ("x'''"); "" when e was added.
  std::string add(const GiNaC::ex& e);

  /// The quantity e uses that the model does not compute, as add() would name it; "" when none.
  std::string missing(const GiNaC::ex& e) const;

  std::size_t size() const noexcept { return expressions_.size(); }
  /// The expressions' values at one sample; NaN where one is not a finite real number there
  /// (sqrt of a negative number, a division by zero).
  /// The GiNaC work it may do (the first call's lowering, GiNaC's evaluation of what cannot be
  /// lowered) holds the symbolic lock (nhc/long_work.hpp): a run may call it without.
  std::vector<double> evaluate(const runtime::Sample& sample) const;
  /// The same with the free symbols' values (in the constructor's order).
  std::vector<double> evaluate(const runtime::Sample& sample, const std::vector<double>& free) const;
  /// Lowers the expressions now, as the first evaluate() would: a run that evaluates them
  /// without the symbolic lock then does no symbolic work unless an expression cannot be lowered.
  void prepare() const;

 private:
  /// Where a symbol's value is found in a sample: y[index], y'[index], or the input u[index].
  enum class Slot { state, derivative, input };
  struct Source {
    GiNaC::ex symbol;
    Slot slot;
    int index;
  };
  static double value_of(const Source& s, const runtime::Sample& sample);
  /// Finds the sources of e's jet symbols (appended to `found`); the first quantity the model
  /// does not compute, or "".
  std::string locate(const GiNaC::ex& e, std::vector<Source>& found) const;

  const Scene* scene_;
  const runtime::Model* model_;
  GiNaC::exmap parameters_;
  std::vector<GiNaC::ex> expressions_;  // parameters already substituted
  std::vector<Source> sources_;
  GiNaC::exset bound_;
  std::vector<GiNaC::ex> free_;  ///< symbols whose values evaluate() is given
  /// The expressions lowered once (inputs: t, then the sources' symbols), made on the first
  /// evaluate(): GiNaC's substitution per sample costs milliseconds for a rigid body's rotation.
  mutable std::unique_ptr<NumericProgram> program_;
  mutable bool substitute_ = false;  ///< an expression the program cannot lower: GiNaC's evalf for all
};

}  // namespace nhc::app
