#pragma once
/// \file zero_test.hpp
/// \brief Whether an expression is zero as a function, when its form does not show it: the one
/// zero test by evaluation, its sample points and its tolerance (kZeroTestPoints, kZeroTolerance,
/// symbolic_policy.hpp).
///
/// A nonzero analytic function is nonzero at almost every point (Schwartz–Zippel for rational
/// functions), so the expression is evaluated at fixed sample points (the given values, every
/// other symbol at a fixed value in [0.25, 1.25); the same values in every run); it is zero when
/// it vanishes at all of them. Over named intermediates (intermediate.hpp) an expression that
/// vanishes identically need not look zero (docs/intermediates.md, "Caveat: forms that hide a
/// zero"): evaluated through its intermediates, it does.

#include <ginac/ginac.h>

#include <set>

namespace nhc {

/// How a zero test treats named intermediates: through their expressions (the function's value),
/// or as independent symbols (the form's, as GiNaC's own functions see it: work_budget::is_zero).
enum class IntermediateValues { through, as_symbols };

/// The k-th sample point for `symbols` (k < kZeroTestPoints): `given` values kept, every other
/// symbol a fixed value in [0.25, 1.25), in the symbols' order.
GiNaC::exmap sample_point(const std::set<GiNaC::ex, GiNaC::ex_is_less>& symbols, unsigned k,
                          const GiNaC::exmap& given = {});

/// True when e is 0 at every sample point: |e| ≤ kZeroTolerance · max(1, its largest term) there
/// (a sum's terms evaluated one by one with IntermediateValues::as_symbols, else e as a whole).
/// False when it is not, or cannot be evaluated at a point (a pole), or does not become a
/// number. `point` fixes some symbols.
bool vanishes_at_sample_points(const GiNaC::ex& e, const GiNaC::exmap& point = {},
                               IntermediateValues intermediates = IntermediateValues::through);

}  // namespace nhc
