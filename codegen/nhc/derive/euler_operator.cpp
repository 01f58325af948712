#include "nhc/derive/euler_operator.hpp"

#include <algorithm>

#include <limits>

#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

VariationForm VariationForm::first_variation(const GiNaC::ex& F, const JetSpace& jet) {
  // Term by term: each term of a sum is differentiated only by the coordinates it contains, so
  // a Lagrangian of N bodies costs O(N) derivatives of small terms, not N derivatives of the
  // whole sum. The sum of the partial derivatives is ∂F/∂q_i^(k).
  VariationForm form;
  const auto add_term = [&](const GiNaC::ex& term) {
    for (const auto& c : jet.jet_coordinates_in(term)) {
      if (c.kind != VariableKind::coordinate) continue;
      form.add(c.index, c.order, partial_derivative(term, jet.symbol(c)));
    }
  };
  if (GiNaC::is_a<GiNaC::add>(F))
    for (const auto& term : F) add_term(term);
  else add_term(F);
  return form;
}

GiNaC::ex VariationForm::coefficient(int i, int k) const {
  auto it = coefficients_.find({i, k});
  return it == coefficients_.end() ? GiNaC::ex(0) : it->second;
}

void VariationForm::add(int i, int k, const GiNaC::ex& term) {
  auto [it, inserted] = coefficients_.emplace(std::make_pair(i, k), term);
  if (!inserted) it->second += term;
}

int VariationForm::highest_order(int i) const {
  // The keys (i, k) are ordered, so the orders of q_i form one contiguous range.
  int k = -1;
  for (auto it = coefficients_.lower_bound({i, std::numeric_limits<int>::min()});
       it != coefficients_.end() && it->first.first == i; ++it)
    if (!it->second.is_zero()) k = std::max(k, it->first.second);
  return k;
}

bool VariationForm::integrate_by_parts_once(int i, const JetSpace& jet) {
  const int k = highest_order(i);
  if (k <= 0) return false;
  const GiNaC::ex a = coefficients_.at({i, k});
  coefficients_.erase({i, k});
  // ∫ A δq^(k) dt = [A δq^(k−1)] − ∫ D(A) δq^(k−1) dt, the bracket vanishing at the ends.
  add(i, k - 1, -jet.total_derivative(a));
  return true;
}

std::vector<GiNaC::ex> euler_operator(const GiNaC::ex& F, const JetSpace& jet) {
  VariationForm form = VariationForm::first_variation(F, jet);
  std::vector<GiNaC::ex> result;
  for (int i = 0; i < jet.coordinate_count(); ++i) {
    while (form.integrate_by_parts_once(i, jet)) {
    }
    result.push_back(simplify_expression(form.coefficient(i, 0)));
  }
  return result;
}

std::vector<GiNaC::ex> euler_operator_closed_form(const GiNaC::ex& F, const JetSpace& jet) {
  std::vector<GiNaC::ex> result;
  for (int i = 0; i < jet.coordinate_count(); ++i) {
    GiNaC::ex sum = 0;
    const int m = jet.highest_order(F, VariableKind::coordinate, i);
    for (int k = 0; k <= m; ++k) {
      const GiNaC::ex partial = partial_derivative(F, jet.symbol({VariableKind::coordinate, i, k}));
      sum += (k % 2 == 0 ? 1 : -1) * jet.total_derivative(partial, k);
    }
    result.push_back(simplify_expression(sum));
  }
  return result;
}

}  // namespace nhc
