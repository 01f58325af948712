#include "nhc/derive/trigonometric_simplification.hpp"

namespace nhc {

namespace {

std::size_t node_count(const GiNaC::ex& e) {
  std::size_t n = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) ++n;
  return n;
}

}  // namespace

GiNaC::ex simplify_trigonometric(const GiNaC::ex& e) {
  const GiNaC::ex u = GiNaC::wild();
  if (!e.has(GiNaC::sin(u)) || !e.has(GiNaC::cos(u))) return e;
  GiNaC::ex best = e;
  std::size_t best_size = node_count(e);
  const GiNaC::ex rules[] = {GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2),
                             GiNaC::pow(GiNaC::cos(u), 2) == 1 - GiNaC::pow(GiNaC::sin(u), 2)};
  for (const GiNaC::ex& rule : rules) {
    // subs_options::algebraic also rewrites sin⁴u = (sin²u)², sin³u = sin u · sin²u.
    const GiNaC::ex candidate = e.subs(rule, GiNaC::subs_options::algebraic).expand();
    const std::size_t size = node_count(candidate);
    if (size < best_size) best = candidate, best_size = size;
  }
  return best;
}

}  // namespace nhc
