#include "nhc/app/parameter_values.hpp"

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

}  // namespace nhc::app
