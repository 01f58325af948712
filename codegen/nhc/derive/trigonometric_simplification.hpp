#pragma once
/// \file trigonometric_simplification.hpp
/// \brief sin²u + cos²u = 1 where it shortens an expression (issue 14, item 11): e.g.
/// −a cos²θ λ1 − a λ1 sin²θ → −a λ1, and terms that cancel identically vanish. Applied by
/// simplify_expression (euler_operator.hpp), so to the derived equations and to the hidden
/// constraints the generated code is built from.

#include <ginac/ginac.h>

namespace nhc {

/// The shortest (fewest expression nodes) of e, e with sin²u → 1 − cos²u and e with
/// cos²u → 1 − sin²u (even powers included), each expanded. e itself when it has no sin or cos.
GiNaC::ex simplify_trigonometric(const GiNaC::ex& e);

}  // namespace nhc
