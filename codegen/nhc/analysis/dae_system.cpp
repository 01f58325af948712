#include "nhc/analysis/dae_system.hpp"

#include "nhc/base/primed_name.hpp"

namespace nhc {

std::string prime_name(const std::string& variable, int order) {
  if (order <= 3) return base::primed_name(variable, order);
  return variable + "^(" + std::to_string(order) + ")";
}

std::string derivative_equation_name(const std::string& equation, int order) {
  if (order == 0) return equation;
  if (order == 1) return "D " + equation;
  return "D^" + std::to_string(order) + " " + equation;
}

GiNaC::ex DaeSystem::unknown_symbol(int j, int order) const { return jet->symbol(unknown_coordinate(j, order)); }

JetCoordinate DaeSystem::unknown_coordinate(int j, int order) const {
  const Unknown& u = unknowns.at(static_cast<std::size_t>(j));
  return {u.kind, u.index, order};
}

std::string DaeSystem::derivative_name(int j, int order) const {
  return prime_name(unknowns.at(static_cast<std::size_t>(j)).name, order);
}

DaeSystem dae_system_of(const Scene& scene, const DerivedModel& model) {
  if (!model.applicable)
    throw MathError("the " + to_string(model.kind) + " model is not applicable to scene '" + scene.name +
                    "': " + model.reason);
  DaeSystem system;
  system.model = model.kind;
  system.jet = scene.jet;
  const JetSpace& jet = *scene.jet;
  for (int i = 0; i < jet.coordinate_count(); ++i)
    system.unknowns.push_back({VariableKind::coordinate, i, jet.coordinates()[static_cast<std::size_t>(i)]});
  for (std::size_t i = 0; i < model.equations.size(); ++i) {
    system.equations.push_back(model.equations[i]);
    system.equation_names.push_back("R_" + jet.coordinates()[i]);
  }
  if (model.constraints_are_equations) {
    for (std::size_t a = 0; a < model.constraints.size(); ++a) {
      const int alpha = static_cast<int>(a);
      system.unknowns.push_back({VariableKind::multiplier, alpha, jet.multiplier_name(alpha)});
      system.equations.push_back(model.constraints[a]);
      system.equation_names.push_back("f" + std::to_string(a + 1));
    }
  } else {
    system.monitored_constraints = model.constraints;
    for (std::size_t a = 0; a < model.constraints.size(); ++a)
      system.monitored_constraint_names.push_back("f" + std::to_string(a + 1));
  }
  return system;
}

}  // namespace nhc
