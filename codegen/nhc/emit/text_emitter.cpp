#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/expr/expression_printer.hpp"
#include "nhc/expr/intermediate.hpp"

namespace nhc {

namespace {

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// M_r u' = f_r, entry by entry, with the dependent speeds and the multipliers.
void write_reduced_text(std::ostream& out, const ReducedForm& r) {
  if (!r.available) {
    out << "  multiplier-free form: not available: " << r.reason << "\n";
    return;
  }
  out << "  multiplier-free form M_r u' = f_r on the speeds u = (" << list(r.speeds) << ") (" << r.rule
      << "), evaluated with\n";
  // The dependent speeds, spelled as in the expressions (x_d1 = …).
  for (std::size_t d = 0; d < r.dependent_speeds.size(); ++d)
    out << "  " << to_text(r.dependent_symbols[d]) << " = " << to_text(r.dependent_speeds[d]) << "\n";
  for (unsigned i = 0; i < r.mass_matrix.rows(); ++i)
    for (unsigned j = 0; j < r.mass_matrix.cols(); ++j)
      out << "  M_r[" << r.speeds[i] << "," << r.speeds[j] << "] = " << to_text(r.mass_matrix(i, j)) << "\n";
  for (std::size_t i = 0; i < r.forcing.size(); ++i)
    out << "  f_r[" << r.speeds[i] << "] = " << to_text(r.forcing[i]) << "\n";
  for (std::size_t a = 0; a < r.multipliers.size(); ++a)
    out << "  " << r.multiplier_names[a] << " = " << to_text(r.multipliers[a]) << "\n";
}

}  // namespace

void write_derivation_text(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models) {
  const JetSpace& jet = *scene.jet;
  out << "scene " << scene.name << ": " << jet.coordinate_count() << " coordinates, " << scene.constraint_count()
      << " constraints\n";
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
    if (model.reduced) write_reduced_text(out, *model.reduced);
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
