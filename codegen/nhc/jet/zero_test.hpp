#pragma once
/// \file zero_test.hpp
/// \brief Whether an expression is zero as a function, when its form does not show it.
///
/// Over named intermediates (intermediate.hpp) an expression that vanishes identically, such as
/// a residual's derivative by a wheel angle that enters only through sin² + cos² of a rotation,
/// need not look zero: expansion stops at the intermediates. A nonzero analytic function is
/// nonzero at almost every point, so the expression is evaluated, through its intermediates, at
/// fixed sample points (the given point, every other symbol at a fixed value in [0.25, 1.25);
/// the same values in every run); it is zero when it vanishes at all of them.

#include <ginac/ginac.h>

namespace nhc {

/// True when e is 0 at every sample point (|e| < 1e-9 there); false when it is not, or cannot
/// be evaluated there (a pole), or does not become a number. `point` fixes some symbols.
bool vanishes_at_sample_points(const GiNaC::ex& e, const GiNaC::exmap& point = {});

}  // namespace nhc
