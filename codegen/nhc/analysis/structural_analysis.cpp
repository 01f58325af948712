#include "nhc/analysis/structural_analysis.hpp"

#include <algorithm>
#include <atomic>

#include <stdexcept>

#include "nhc/derive/euler_operator.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/symbol_substitution.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (k > 0) out += k + 1 == names.size() ? " and " : ", ";
    out += names[k];
  }
  return out;
}

void StructuralAnalysis::require_nonsingular() const {
  if (structurally_singular) throw MathError(singular_reason);
}

GiNaC::ex differentiated_equation(const StructuralAnalysis& a, int i, int r) {
  const JetSpace& jet = *a.system.jet;
  GiNaC::ex e = simplify_expression(jet.total_derivative(a.system.equations.at(static_cast<std::size_t>(i)), r));
  GiNaC::exmap vanishing;
  // analyze_structure fills the lookup once; an analysis assembled by hand gets it here.
  std::map<std::pair<VariableKind, int>, int> computed;
  const auto& column = a.column_of_unknown.size() == a.system.unknowns.size() ? a.column_of_unknown
                                                                              : (computed = unknown_columns(a.system));
  for (const JetCoordinate& c : jet.jet_coordinates_in(e)) {
    const auto it = column.find({c.kind, c.index});
    if (it == column.end()) continue;
    const int j = it->second;
    if (c.order <= a.d(j) + r - a.c(i)) continue;
    const GiNaC::symbol& s = jet.symbol(c);
    if (!work_budget::is_zero(partial_derivative(e, s)))
      throw std::logic_error("differentiated equation depends on an order above its offset");
    vanishing[s] = 0;
  }
  if (!vanishing.empty()) e = simplify_expression(substitute_symbols(e, vanishing));
  return e;
}

namespace {

std::string describe_deficiency(const DaeSystem& system, const StructuralDeficiency& def) {
  std::vector<std::string> eqs, unknowns, free_unknowns;
  for (int i : def.rows) eqs.push_back(system.equation_names[static_cast<std::size_t>(i)]);
  for (int j : def.cols) unknowns.push_back(system.unknowns[static_cast<std::size_t>(j)].name);
  for (int j : def.unmatched_cols) free_unknowns.push_back(system.unknowns[static_cast<std::size_t>(j)].name);
  std::string s = "the " + to_string(system.model) + " system is structurally singular: no " +
                  "assignment of equations to distinct unknowns exists (structural rank " +
                  std::to_string(def.matching_size) + " of " + std::to_string(system.size()) + "). ";
  if (eqs.size() == 1) s += "The equation " + eqs.front() + " involves ";
  else s += "The " + std::to_string(eqs.size()) + " equations " + join_names(eqs) + " involve ";
  if (unknowns.empty()) s += "no unknown at all";
  else
    s += "only the " + std::to_string(unknowns.size()) + " unknown" + (unknowns.size() == 1 ? " " : "s ") +
         join_names(unknowns);
  if (!free_unknowns.empty())
    s += ", and " + join_names(free_unknowns) + (free_unknowns.size() == 1 ? " is" : " are") +
         " left without an equation";
  return s;
}

std::atomic<long> analyses{0};

}  // namespace

long analyze_structure_calls() { return analyses.load(); }

StructuralAnalysis analyze_structure(DaeSystem system) {
  ++analyses;
  StructuralAnalysis a;
  a.sigma = signature_matrix(system);
  a.column_of_unknown = unknown_columns(system);
  a.system = std::move(system);
  const auto transversal = highest_value_transversal(a.sigma);
  if (!transversal) {
    a.structurally_singular = true;
    a.deficiency = structural_deficiency(a.sigma);
    a.singular_reason = describe_deficiency(a.system, a.deficiency);
    return a;
  }
  a.transversal = *transversal;
  a.offsets = pryce_offsets(a.sigma, a.transversal);
  const int n = a.system.size();
  int max_c = 0, sum_c = 0, sum_d = 0;
  bool algebraic = false;
  for (int i = 0; i < n; ++i) {
    max_c = std::max(max_c, a.c(i));
    sum_c += a.c(i);
    sum_d += a.d(i);
    algebraic = algebraic || a.d(i) == 0;
  }
  a.index = max_c + (algebraic ? 1 : 0);
  a.dof = sum_d - sum_c;
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < a.d(j); ++k) a.initial_values_needed.push_back(a.system.unknown_coordinate(j, k));
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < a.c(i); ++r)
      a.hidden_constraints.push_back(
          {i, r, derivative_equation_name(a.system.equation_names[static_cast<std::size_t>(i)], r)});
  return a;
}

}  // namespace nhc
