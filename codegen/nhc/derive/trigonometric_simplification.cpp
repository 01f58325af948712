#include "nhc/derive/trigonometric_simplification.hpp"

#include "nhc/jet/work_budget.hpp"

namespace nhc {

GiNaC::ex simplify_trigonometric(const GiNaC::ex& e) {
  const GiNaC::ex u = GiNaC::wild();
  if (!work_budget::worth_trigonometric_simplification(e) || !e.has(GiNaC::sin(u)) || !e.has(GiNaC::cos(u)))
    return e;
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

}  // namespace nhc
