#include "nhc/app/parameter_overrides.hpp"

#include <algorithm>
#include <cmath>

#include "nhc/app/parameter_values.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/jet_space.hpp"
#include "nhc/runtime/sensitivity.hpp"

namespace nhc::app {

std::pair<std::string, std::string> split_assignment(const std::string& flag, const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError({flag, 0, 0}, text + ": expected NAME=VALUE");  // the flag is the location
  return {text.substr(0, eq), text.substr(eq + 1)};
}

double parse_number(const std::string& flag, const std::string& text, const std::string& written) {
  size_t used = 0;
  double v = NAN;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(v))
    throw InputError({flag, 0, 0}, (written.empty() ? "" : written + ": ") + "'" + text + "' is not a number");
  return v;
}

std::vector<ParameterOverride> parse_parameter_overrides(const Scene& scene,
                                                         const std::vector<std::string>& assignments) {
  std::vector<ParameterOverride> overrides;
  for (const std::string& a : assignments) {
    const auto [name, value] = split_assignment("--set", a);
    // The message names the flag once (its location) and quotes the assignment as written.
    check_parameter_name(scene, name, "--set", a);
    const double v = parse_number("--set", value, a);
    check_parameter_value(scene, name, v, "--set", a);  // Python's set= obeys the same
    overrides.push_back({name, v});
  }
  return overrides;
}

void apply_parameter_overrides(Scene& scene, const std::vector<ParameterOverride>& overrides) {
  std::vector<std::pair<std::string, double>> values;
  for (const ParameterOverride& o : overrides) values.emplace_back(o.name, o.value);
  set_parameter_values(scene, values);  // the rule Python's set= follows too
}

std::vector<double> parameters_with_overrides(const runtime::Model& model,
                                              const std::vector<ParameterOverride>& overrides) {
  std::vector<double> p = model.default_parameters();
  for (const ParameterOverride& o : overrides) {
    const int i = model.parameter_index(o.name);
    if (i >= 0) p[static_cast<std::size_t>(i)] = o.value;
  }
  return p;
}

void refuse_unread_parameter(const Scene& scene, const runtime::Model& model, const std::string& name,
                             const std::string& flag, const std::string& consequence) {
  if (!scene.jet->parameter_index(name) || model.parameter_index(name) >= 0) return;
  // Nor does one a contact's mu, the controller's period or [simulate] is written through.
  if (const std::vector<std::string> numbers = experiment_numbers_using(scene, name); !numbers.empty())
    throw InputError({flag, 0, 0}, "the " + model.model_name() + " model's equations do not contain the parameter '" +
                                       name + "', only the scene's " + numbers.front() + " does, which " + flag +
                                       " does not follow: run with --set " + name + "=… (Python: set=) for each value");
  throw InputError({flag, 0, 0}, "the " + model.model_name() + " model's equations do not contain the parameter '" +
                                     name + "': " + consequence);
}

std::vector<runtime::SensitivityParameter> sensitivity_parameters(const Scene& scene, const runtime::Model& model,
                                                                  const std::vector<std::string>& names,
                                                                  const std::string& flag) {
  std::vector<runtime::SensitivityParameter> thetas;
  try {
    if (names.empty()) throw std::invalid_argument("no quantity to differentiate by");
    for (const std::string& name : names) {
      if (std::count(names.begin(), names.end(), name) > 1) throw std::invalid_argument(name + " is named twice");
      // ∂y(t0)/∂θ of the given values written through θ (x = ["A", 0.0]): where the start moves.
      const std::vector<double> slopes = initial_slopes(scene, model, name);
      const bool moves_start = std::any_of(slopes.begin(), slopes.end(), [](double s) { return s != 0; });
      runtime::SensitivityParameter theta;
      if (moves_start && model.parameter_index(name) < 0) {  // only the start: ∂F/∂θ = 0
        theta.kind = runtime::SensitivityParameter::Kind::start;
        theta.index = -1;
        theta.name = name;
        theta.value = scene.parameter_values.at(static_cast<std::size_t>(*scene.jet->parameter_index(name)));
      } else {
        refuse_unread_parameter(scene, model, name, flag, "its sensitivities are all zero");
        theta = runtime::sensitivity_parameter(model, name);
      }
      if (moves_start) theta.initial_slope = slopes;
      thetas.push_back(std::move(theta));
    }
  } catch (const std::invalid_argument& e) {
    throw InputError({flag, 0, 0}, e.what());
  }
  return thetas;
}

}  // namespace nhc::app
