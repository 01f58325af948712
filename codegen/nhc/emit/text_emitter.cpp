#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/jet/expression_printer.hpp"

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
}

}  // namespace nhc
