#include "nhc/expr/simplification.hpp"

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

GiNaC::ex simplify_trigonometric(const GiNaC::ex& e) {
  const GiNaC::ex u = GiNaC::wild();
  if (!work_budget::worth_trigonometric_simplification(e) || !e.has(GiNaC::sin(u)) || !e.has(GiNaC::cos(u))) return e;
  GiNaC::ex best = e;
  std::size_t best_size = work_budget::node_count(e);
  const GiNaC::ex rules[] = {GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2),
                             GiNaC::pow(GiNaC::cos(u), 2) == 1 - GiNaC::pow(GiNaC::sin(u), 2)};
  for (const GiNaC::ex& rule : rules) {
    // subs_options::algebraic also rewrites sin⁴u = (sin²u)², sin³u = sin u · sin²u.
    const GiNaC::ex candidate = work_budget::expand(e.subs(rule, GiNaC::subs_options::algebraic));
    const std::size_t size = work_budget::node_count(candidate);
    if (size < best_size) best = candidate, best_size = size;
  }
  return best;
}

GiNaC::ex simplify_expression(const GiNaC::ex& e) {
  // Expanding cancels polynomial terms. Terms over different powers of one radical, such as
  // x'^2 v^-3 - v^-1 with v = sqrt(x'^2 + y'^2), cancel only over a common denominator:
  // normal() finds it, and expanding its numerator shows the cancellation (-y'^2 v^-3).
  // Keep whichever form is smaller. Both steps past expansion only make the result smaller, so
  // large sums skip them (work_budget.hpp decides where).
  const GiNaC::ex expanded = work_budget::expand(substituted_where_small(e));
  if (!work_budget::worth_simplifying(expanded)) return simplify_trigonometric(expanded);
  const GiNaC::ex fraction = expanded.normal().numer_denom();
  const GiNaC::ex combined = work_budget::expand(fraction.op(0)) / fraction.op(1);
  return simplify_trigonometric(work_budget::node_count(combined) < work_budget::node_count(expanded) ? combined
                                                                                                      : expanded);
}

}  // namespace nhc
