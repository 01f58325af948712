#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/jet/expression_printer.hpp"
#include "nhc/jet/intermediate.hpp"

namespace nhc {

void write_derivation_text(std::ostream& out, const Scene& scene,
                           const std::vector<DerivedModel>& models) {
  const JetSpace& jet = *scene.jet;
  out << "scene " << scene.name << ": " << jet.coordinate_count() << " coordinates, "
      << scene.constraint_count() << " constraints\n";
  out << "  L = " << to_text(scene.lagrangian) << "\n";
  for (std::size_t a = 0; a < scene.constraints.size(); ++a)
    out << "  f" << a + 1 << " = " << to_text(scene.constraints[a]) << "\n";
  for (const DerivedModel& model : models) {
    out << "\n" << to_string(model.kind) << ":\n";
    if (!model.applicable) {
      out << "  not applicable: " << model.reason << "\n";
      continue;
    }
    for (std::size_t i = 0; i < model.equations.size(); ++i)
      out << "  R_" << jet.coordinates()[i] << " = " << to_text(model.equations[i]) << " = 0\n";
    for (std::size_t a = 0; a < model.constraints.size(); ++a)
      out << "  " << (model.constraints_are_equations ? "f" : "monitored f") << a + 1 << " = "
          << to_text(model.constraints[a]) << " = 0\n";
  }
  const std::vector<GiNaC::ex> where = derivation_intermediates(scene, models);
  if (where.empty()) return;
  // The scene's own quantities; their derivatives go by their names, as a textbook writes ∂T/∂φ.
  out << "\nwhere (each after the ones it uses; dX_dz stands for the partial derivative of X by z and\n"
         "X_dot for its time derivative; --format json lists their expressions, --expand substitutes all):\n";
  for (const GiNaC::ex& d : where) {
    const auto& i = GiNaC::ex_to<Intermediate>(d);
    if (i.origin() != Intermediate::Origin::defined) continue;
    out << "  " << i.intermediate_name() << " = " << to_text(i.expression()) << "\n";
  }
}

}  // namespace nhc
