#include "nhc/emit/model_layout.hpp"

namespace nhc {

ModelLayout model_layout(const Scene& scene, const Index1System& system, const PreparedModel& m) {
  ModelLayout layout;
  for (const StateComponent& s : system.states) {
    layout.state_names.push_back(s.name);
    layout.state_variable.push_back(s.kind == VariableKind::coordinate ? s.index : m.n_coordinates + s.index);
    layout.state_order.push_back(s.order);
    layout.differential_id.push_back(s.differential ? 1.0 : 0.0);
  }
  layout.residual_names = system.residual_names;
  layout.residual_names.resize(static_cast<std::size_t>(m.n_states));
  for (int k : m.parameters)
    layout.default_parameters.push_back(scene.parameter_values.at(static_cast<std::size_t>(k)));
  if (m.n_hidden > 0) {
    layout.hidden_names = system.hidden_constraint_names;
    layout.hidden_names.resize(static_cast<std::size_t>(m.n_hidden));
  }
  for (const auto& invariant : m.invariants) layout.invariant_names.push_back(invariant.name);
  for (const auto& r : m.reference) layout.reference_coordinate.push_back(r.first);
  for (const auto& q : m.singular) layout.singular_names.push_back(q.name);
  layout.speed_coordinate = m.speed_coordinate;
  return layout;
}

}  // namespace nhc
