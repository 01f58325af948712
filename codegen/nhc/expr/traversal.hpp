#pragma once
/// \file traversal.hpp
/// \brief The one walk over a GiNaC expression's distinct subexpressions: shared subtrees are
/// read once (definitions that square the previous one share their subtrees, and a walk per path
/// would be exponential) and without recursion (a chain of thousands of definitions).

#include <ginac/ginac.h>

#include <unordered_set>
#include <vector>

namespace nhc {

/// Calls visit(x) on every distinct subexpression x of e once, depth first, a node before its
/// operands and the operands last to first; visit returns whether to go into x's operands.
template <class Visit>
void visit_distinct(const GiNaC::ex& e, Visit visit) {
  std::unordered_set<GiNaC::ex, std::hash<GiNaC::ex>, GiNaC::ex_is_equal> seen;
  std::vector<GiNaC::ex> stack{e};
  while (!stack.empty()) {
    const GiNaC::ex x = stack.back();
    stack.pop_back();
    if (!seen.insert(x).second || !visit(x)) continue;
    for (std::size_t k = 0; k < x.nops(); ++k) stack.push_back(x.op(k));
  }
}

/// Whether some subexpression of e (e included) satisfies `test`.
template <class Test>
bool any_subexpression(const GiNaC::ex& e, Test test) {
  bool found = false;
  visit_distinct(e, [&](const GiNaC::ex& x) {
    if (!found && test(x)) found = true;
    return !found;
  });
  return found;
}

}  // namespace nhc
