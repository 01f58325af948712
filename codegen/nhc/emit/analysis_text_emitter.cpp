#include <algorithm>

#include "nhc/base/number_text.hpp"
#include <cmath>
#include <iomanip>
#include <sstream>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/emit/analysis_emitters.hpp"
#include "nhc/expr/expression_printer.hpp"

namespace nhc {

namespace {

std::string pad(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}

std::string ten_digits(double v) { return base::number_text(v, 10); }

/// Above this many unknowns σ is listed by rows (finite entries only) instead of as a table,
/// whose size would grow as n².
constexpr int kSigmaTableLimit = 40;

void write_sigma_rows(std::ostream& out, const StructuralAnalysis& a) {
  const bool offsets = !a.structurally_singular;
  out << "  signature matrix by rows (" << a.sigma.rows() << " equations, " << a.sigma.cols()
      << " unknowns; only the finite entries, unknown=order" << (offsets ? ", * on a highest-value transversal" : "")
      << "):\n";
  for (int i = 0; i < a.sigma.rows(); ++i) {
    out << "    " << a.system.equation_names[static_cast<std::size_t>(i)] << ":";
    for (const auto& e : a.sigma.row(i)) {
      out << " " << a.system.unknowns[static_cast<std::size_t>(e.col)].name << "=" << e.value;
      if (offsets && a.transversal.column_of_row[static_cast<std::size_t>(i)] == e.col) out << "*";
    }
    if (offsets) out << "   c = " << a.c(i);
    out << "\n";
  }
  if (offsets) {
    out << "    d:";
    for (int j = 0; j < a.sigma.cols(); ++j)
      out << " " << a.system.unknowns[static_cast<std::size_t>(j)].name << "=" << a.d(j);
    out << "\n    (transversal value " << a.transversal.value << ")\n";
  }
}

void write_sigma(std::ostream& out, const StructuralAnalysis& a) {
  if (a.sigma.cols() > kSigmaTableLimit) {
    write_sigma_rows(out, a);
    return;
  }
  std::size_t width = 3, label = 0;
  for (const auto& u : a.system.unknowns) width = std::max(width, u.name.size() + 1);
  for (const auto& e : a.system.equation_names) label = std::max(label, e.size());
  const bool offsets = !a.structurally_singular;
  out << "  signature matrix (rows: equations, columns: unknowns, '-' absent)";
  out << (offsets ? ", offsets c and d:\n" : ":\n");
  out << "    " << std::string(label, ' ');
  for (const auto& u : a.system.unknowns) out << pad(u.name, width + 1);
  if (offsets) out << pad("c", 5);
  out << "\n";
  for (int i = 0; i < a.sigma.rows(); ++i) {
    out << "    " << a.system.equation_names[static_cast<std::size_t>(i)]
        << std::string(label - a.system.equation_names[static_cast<std::size_t>(i)].size(), ' ');
    for (int j = 0; j < a.sigma.cols(); ++j) {
      std::string cell = a.sigma.present(i, j) ? std::to_string(a.sigma(i, j)) : "-";
      if (offsets && a.transversal.column_of_row[static_cast<std::size_t>(i)] == j) cell += "*";
      else cell += " ";
      out << pad(cell, width + 1);
    }
    if (offsets) out << pad(std::to_string(a.c(i)), 5);
    out << "\n";
  }
  if (offsets) {
    out << "    " << pad("d", label);
    for (int j = 0; j < a.sigma.cols(); ++j) out << pad(std::to_string(a.d(j)) + " ", width + 1);
    out << "\n    (* marks a highest-value transversal, value " << a.transversal.value << ")\n";
  }
}

void write_one(std::ostream& out, const Scene& scene, const ModelAnalysis& m) {
  out << "\n" << to_string(m.model) << ":\n";
  if (!m.applicable) {
    for (const auto& e : m.errors) out << "  error: " << e << "\n";
    return;
  }
  const StructuralAnalysis& a = *m.structure;
  std::vector<std::string> unknowns;
  for (const auto& u : a.system.unknowns) unknowns.push_back(u.name);
  out << "  unknowns:  " << join_names(unknowns) << "\n";
  out << "  equations: " << join_names(a.system.equation_names) << "\n";
  write_sigma(out, a);
  if (!a.structurally_singular) {
    out << "  structural index " << a.index << ", " << a.dof << " degrees of freedom\n";
    std::vector<std::string> needed;
    for (const auto& c : a.initial_values_needed)
      needed.push_back(prime_name(a.system.jet->variable_name(c.kind, c.index), c.order));
    out << "  initial values needed (" << needed.size()
        << "): " << (needed.empty() ? std::string("none") : join_names(needed)) << "\n";
    if (a.hidden_constraints.empty()) {
      out << "  hidden constraints: none\n";
    } else {
      out << "  hidden constraints (" << a.hidden_constraints.size() << "):\n";
      for (const auto& h : a.hidden_constraints)
        out << "    " << h.name << ": " << to_text(differentiated_equation(a, h.equation, h.order)) << " = 0\n";
    }
  }
  if (m.initial) {
    out << "  consistent initial point at t0 = " << ten_digits(m.initial->t0) << ":\n";
    for (const InitialValue& v : m.initial->values)
      out << "    " << v.name << " = " << ten_digits(v.value) << " (" << to_string(v.source) << ")\n";
    std::vector<std::string> leading;
    for (const InitialValue& v : m.initial->leading) leading.push_back(v.name + " = " + ten_digits(v.value));
    out << "    leading derivatives " << (m.initial->leading_solved ? "" : "(not solved) ") << join_names(leading)
        << "\n";
    for (const auto& n : m.initial->notes) out << "  note: " << n << "\n";
  }
  if (m.jacobian) {
    out << "  system Jacobian at t0: condition number "
        << (std::isfinite(m.jacobian_condition) ? ten_digits(m.jacobian_condition) : std::string("infinite"))
        << (m.jacobian_condition_estimated ? " (1-norm estimate: above " + std::to_string(kExactConditionLimit) +
                                                 " unknowns the exact 2-norm one is not computed)"
                                           : std::string())
        << "\n";
  }
  for (const auto& e : m.errors) out << "  error: " << e << "\n";
  (void)scene;
}

}  // namespace

void write_analysis_text(std::ostream& out, const Scene& scene, const std::vector<ModelAnalysis>& analyses) {
  out << "scene " << scene.name << ": " << scene.coordinate_count() << " coordinates, " << scene.constraint_count()
      << " constraints; Pryce's structural analysis\n";
  for (const auto& m : analyses) write_one(out, scene, m);
}

}  // namespace nhc
