#include "nhc/app/parameter_values.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "nhc/runtime/integrator.hpp"
#include "nhc/scene/constant_expression.hpp"

namespace nhc::app {

void set_parameter_values(Scene& scene, const std::vector<std::pair<std::string, double>>& values) {
  for (const auto& [name, value] : values)
    scene.parameter_values.at(static_cast<std::size_t>(scene.jet->parameter_index(name).value())) = value;
  if (!values.empty()) reevaluate_initial_expressions(scene);  // [initial] values written through parameters follow
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
