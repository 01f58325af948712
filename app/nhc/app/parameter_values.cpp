#include "nhc/app/parameter_values.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include "nhc/errors.hpp"
#include "nhc/runtime/integrator.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/tolerances.hpp"

namespace nhc::app {

namespace {

/// The parameters' values as a list "a = 1, b = 2" of those `text` names (for a refusal's words).
std::string values_named_in(const std::string& text, const std::map<std::string, double>& names) {
  std::string list;
  for (const auto& [name, value] : names) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
      const auto word = [&](std::size_t i) {
        return i < text.size() && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_');
      };
      if ((at > 0 && word(at - 1)) || word(at + name.size())) continue;
      list += (list.empty() ? "" : ", ") + name + " = " + base::shortest_text(value);
      break;
    }
  }
  return list;
}

/// Why a value cannot stand at a place ("" when it can).
using ValueProblem = std::string (*)(double);
std::string any_number(double) { return ""; }
std::string positive(double v) { return v > 0 ? "" : "must be positive"; }
std::string non_negative(double v) { return v >= 0 ? "" : "must not be negative"; }
std::string positive_period(double v) {
  return v > 0 ? "" : "must be a positive number (the controller's sample period h)";
}

/// Each of the experiment's numbers that may be written through the parameters, in a fixed order,
/// as f(what, key, value, expression, problem): its words ("mu of contact 'floor'"), its key as a
/// refusal names it ("mu"), the number (null when the scene has none: a step not given), its text
/// and place, and the rule its values obey. One list for re-evaluating and for looking up.
template <class SceneT, class F>
void visit_experiment_numbers(SceneT& scene, F&& f) {
  f("[initial] t0", "t0", &scene.initial.t0, scene.initial.t0_expression, any_number);
  for (auto& c : scene.contacts) f("mu of contact '" + c.name + "'", "mu", &c.mu, c.mu_expression, non_negative);
  if (scene.controller.present) {
    f("[controller] period", "period", &scene.controller.period, scene.controller.period_expression, positive_period);
    for (auto& s : scene.controller.states)
      f("[controller] state '" + s.name + "'", "controller state '" + s.name + "'", &s.initial, s.initial_expression,
        any_number);
  }
  auto& run = scene.simulate;
  // t_end after t0 is the run's check (run_t_end): a t_end from outside may stand in for it.
  f("[simulate] t_end", "t_end", &run.t_end, run.t_end_expression, any_number);
  f("[simulate] rtol", "rtol", &run.rtol, run.rtol_expression, relative_tolerance_problem);
  f("[simulate] atol", "atol", &run.atol, run.atol_expression, positive);
  f("[simulate] max_step", "max_step", run.max_step ? &*run.max_step : nullptr, run.max_step_expression, positive);
  f("[simulate] initial_step", "initial_step", run.initial_step ? &*run.initial_step : nullptr,
    run.initial_step_expression, positive);
}

/// `number` re-evaluated from its text when it has one; a value `problem` refuses is refused at
/// the place (exit 2) in the key's words.
void reevaluate(double& number, const NumberExpression& source, const std::string& key,
                const std::map<std::string, double>& names, ValueProblem problem) {
  if (source.empty()) return;
  const std::string values = values_named_in(source.text, names);
  const std::string with = values.empty() ? "" : " at " + values;
  double v = 0;
  try {
    v = evaluate_constant_expression(source.text, names);
  } catch (const std::invalid_argument& e) {
    throw InputError(source.where, key + " = \"" + source.text + "\"" + with + ": " + e.what());
  }
  if (const std::string why = problem(v); !why.empty())
    throw InputError(source.where,
                     key + " = \"" + source.text + "\" is " + base::shortest_text(v) + with + ": " + key + " " + why);
  number = v;
}

}  // namespace

void reevaluate_experiment_numbers(Scene& scene) {
  const std::map<std::string, double> names = scene.parameter_values_by_name();
  visit_experiment_numbers(scene, [&](const std::string&, const std::string& key, double* value,
                                      const NumberExpression& source, ValueProblem problem) {
    if (value) reevaluate(*value, source, key, names, problem);
  });
  // Without [simulate] t_end a run lasts 1 from t0 (scene_loader.cpp): from this t0.
  if (!scene.initial.t0_expression.empty() && scene.simulate.t_end_expression.where.line <= 0)
    scene.simulate.t_end = scene.initial.t0 + 1.0;
}

void for_each_experiment_number(const Scene& scene,
                                const std::function<void(const std::string&, const NumberExpression&)>& f) {
  visit_experiment_numbers(scene, [&](const std::string& what, const std::string&, const double*,
                                      const NumberExpression& source, ValueProblem) { f(what, source); });
}

namespace {

/// experiment_numbers_using() of the numbers whose key `take` accepts.
std::vector<std::string> numbers_using(const Scene& scene, const std::string& name,
                                       const std::function<bool(const std::string&)>& take) {
  std::vector<std::string> found;
  const std::optional<int> k = scene.jet->parameter_index(name);
  if (!k) return found;
  Scene moved = scene;
  double& value = moved.parameter_values.at(static_cast<std::size_t>(*k));
  value += 1e-3 * std::max(1.0, std::abs(value));
  const std::map<std::string, double> here = scene.parameter_values_by_name(), there = moved.parameter_values_by_name();
  // Written through the parameter, directly or through parameters computed from it: its value moves.
  visit_experiment_numbers(scene, [&](const std::string& what, const std::string& key, const double*,
                                      const NumberExpression& number, ValueProblem) {
    if (number.empty() || !take(key)) return;
    const auto at = [&](const std::map<std::string, double>& names) -> std::optional<double> {
      try {
        return evaluate_constant_expression(number.text, names);
      } catch (const std::invalid_argument&) {
        return std::nullopt;
      }
    };
    if (at(here) != at(there)) found.push_back(what + " (" + number.where.str() + ")");
  });
  return found;
}

}  // namespace

std::vector<std::string> experiment_numbers_using(const Scene& scene, const std::string& name) {
  return numbers_using(scene, name, [](const std::string&) { return true; });
}

std::vector<std::string> run_grid_numbers_using(const Scene& scene, const std::string& name) {
  return numbers_using(scene, name,
                       [](const std::string& key) { return key != "mu" && key.rfind("controller state ", 0) != 0; });
}

void set_parameter_values(Scene& scene, const std::vector<std::pair<std::string, double>>& values) {
  for (const auto& [name, value] : values)
    scene.parameter_values.at(static_cast<std::size_t>(scene.jet->parameter_index(name).value())) = value;
  if (values.empty()) return;
  reevaluate_initial_expressions(scene);  // [initial] values written through parameters follow
  reevaluate_experiment_numbers(scene);   // and mu, period, [simulate]'s numbers
}

std::vector<double> model_parameters(const runtime::Model& model, const Scene& scene) {
  std::vector<double> p = model.default_parameters();
  for (int k = 0; k < model.n_parameters(); ++k)
    if (const auto q = scene.jet->parameter_index(model.table().parameter_names[k]))
      p[static_cast<std::size_t>(k)] = scene.parameter_values[static_cast<std::size_t>(*q)];
  return p;
}

std::vector<double> initial_slopes(const Scene& scene, const runtime::Model& model, const std::string& name) {
  std::vector<double> slopes(static_cast<std::size_t>(model.n_states()), 0.0);
  const std::optional<int> k = scene.jet->parameter_index(name);
  if (!k || scene.initial.expressions.empty()) return slopes;
  const double value = scene.parameter_values.at(static_cast<std::size_t>(*k));
  const double h = 1e-6 * std::max(1.0, std::abs(value));
  // The [initial] values re-evaluated with the parameter at v (the parameters computed from it too).
  const auto start = [&](double v) {
    Scene moved = scene;
    moved.parameter_values.at(static_cast<std::size_t>(*k)) = v;
    const std::map<std::string, double> names = moved.parameter_values_by_name();
    std::map<std::string, std::vector<double>> values = scene.initial.values;
    for (const auto& [variable, texts] : scene.initial.expressions)
      for (std::size_t j = 0; j < texts.size() && j < values[variable].size(); ++j)
        if (!texts[j].empty()) values[variable][j] = evaluate_constant_expression(texts[j], names);
    return runtime::initial_state_from(model, scene.initial.t0, values);
  };
  const runtime::InitialState plus = start(value + h), minus = start(value - h);
  for (std::size_t i = 0; i < slopes.size(); ++i)
    if (plus.given[i]) slopes[i] = (plus.y[i] - minus.y[i]) / (2 * h);
  return slopes;
}

}  // namespace nhc::app
