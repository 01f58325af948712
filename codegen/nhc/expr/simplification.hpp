#pragma once
/// \file simplification.hpp
/// \brief The simplification nhc applies to what it derives: expansion, a common denominator
/// where it is shorter, and sin²u + cos²u = 1 where it shortens (e.g.
/// −a cos²θ λ1 − a λ1 sin²θ → −a λ1). Applied to the derived equations, the hidden constraints
/// and the Jacobians, and to the named intermediates small enough for it (intermediate.hpp);
/// work_budget.hpp bounds the work.

#include <ginac/ginac.h>

namespace nhc {

/// The shortest (fewest expression nodes) of e, e with sin²u → 1 − cos²u and e with
/// cos²u → 1 − sin²u (even powers included), each expanded. e itself when it has no sin or cos.
GiNaC::ex simplify_trigonometric(const GiNaC::ex& e);

/// Brings an expression to the canonical form nhc shows and analyses: fully expanded, so that
/// polynomial cancellations (e.g. λ q''' in the paper's Example 1) show, over a common
/// denominator where that is shorter, then simplify_trigonometric. Intermediates count as symbols.
GiNaC::ex simplify_expression(const GiNaC::ex& e);

}  // namespace nhc
