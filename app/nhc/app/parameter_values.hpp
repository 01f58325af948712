#pragma once
/// \file parameter_values.hpp
/// \brief Parameter values given from outside a scene (the command line's `--set`, Python's
/// `set=`): the one rule that assigns them, and the model's parameter vector read from a scene by
/// name. Parameters are run-time values of a compiled model, so a changed value never asks for a
/// new one: the header is generated and compiled from the scene as written (its defaults), and a
/// run passes model_parameters() of the scene with the values set (docs/python.md, "Parameter
/// studies").

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// Each (name, value) assigned to the scene's parameter of that name, in order (the last of a
/// repeated name wins), then the [initial] values written through parameters re-evaluated, and
/// the experiment's other numbers written through them (reevaluate_experiment_numbers()).
/// The names and values must have passed check_parameter_value() (run_request.hpp).
void set_parameter_values(Scene& scene, const std::vector<std::pair<std::string, double>>& values);

/// The experiment's numbers written as expressions of the parameters (NumberExpression: [initial]
/// t0, a contact's mu, [controller] period and states, [simulate] t_end, rtol, atol, max_step,
/// initial_step) re-evaluated at the scene's parameter values. A value the place does not allow
/// (mu < 0, a period, tolerance or step that is not positive, an expression that is
/// not a finite number) is an InputError at the place in the scene file, naming the parameters'
/// values (exit 2).
void reevaluate_experiment_numbers(Scene& scene);

/// Each of the experiment's numbers that may be written through the parameters, with its words
/// ("mu of contact 'floor'", "[simulate] t_end"), in a fixed order.
void for_each_experiment_number(const Scene& scene,
                                const std::function<void(const std::string&, const NumberExpression&)>& f);

/// The experiment's numbers whose value moves with the parameter `name` (written through it,
/// or through a parameter computed from it), each as "WHAT (FILE:LINE:COLUMN)".
std::vector<std::string> experiment_numbers_using(const Scene& scene, const std::string& name);

/// Those of experiment_numbers_using() that place the run in time and set its accuracy: [initial]
/// t0, the controller's period and [simulate]'s numbers (t_end, tolerances, steps), which runs
/// compared on the same output times share (nhc ensemble); not a contact's mu or a controller
/// state's start value, which each run evaluates at its own parameters.
std::vector<std::string> run_grid_numbers_using(const Scene& scene, const std::string& name);

/// ∂y_i(0)/∂θ of the states `model` takes from `scene`'s [initial] for the parameter `name`:
/// central differences of the [initial] values written through parameters, re-evaluated (with the
/// parameters computed from it) at θ ± 1e-6 max(1, |θ|); the values are constant expressions, so
/// the error is rounding, about 1e-10 of the slope. All zero when [initial] does not use it.
std::vector<double> initial_slopes(const Scene& scene, const runtime::Model& model, const std::string& name);

/// The model's parameters (runtime::Model::parameter_names order) at the scene's values, by name:
/// a model compiled from the scene as written runs the scene with `--set` values exactly as one
/// compiled from the changed scene would.
std::vector<double> model_parameters(const runtime::Model& model, const Scene& scene);

}  // namespace nhc::app
