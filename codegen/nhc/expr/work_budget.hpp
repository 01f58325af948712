#pragma once
/// \file work_budget.hpp
/// \brief The work budget of the symbolic pipeline: every operation whose cost can grow without
/// bound in the size of its input goes through here; its limits are in symbolic_policy.hpp.
///
/// Two kinds of limit:
/// - a *refusal* limit for work the pipeline cannot do without: expansion. Its result size is
///   bounded from the structure before any work is done (sums add, products multiply, an integer
///   power k of an n-term sum has at most C(n+k−1, k) terms, a negative one as many in its
///   denominator), and so is its size (the factors of all those terms); past kMaxExpandedTerms
///   terms or kMaxExpandedFactors factors the operation throws WorkLimitExceeded, which the
///   callers that know the scene turn into an InputError at the expression (exit 2).
/// - a *simplification* threshold for work that only makes results smaller: common denominators
///   (normal()), sin² + cos² = 1 and exact zero tests. Below kMaxSimplifiedTerms (for sin² + cos² = 1:
///   kMaxTrigonometricTerms) they run; above,
///   the expression is kept as it is (expanded, not simplified), and a zero test falls back to
///   evaluation at fixed sample points.
/// Printers never expand (expression_printer.cpp): printing is linear in the size of the tree.

#include <ginac/ginac.h>

#include <cstddef>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/expr/symbolic_policy.hpp"

namespace nhc::work_budget {

/// The deepest nesting of function calls in e (0 for a polynomial, 1 for sin(x), 2 for
/// sqrt(sin(x)), …); stops counting past `limit`.
std::size_t function_nesting(const GiNaC::ex& e, std::size_t limit = kMaxSimplifiedNesting + 1);

/// What e.expand() would build, predicted from e's structure before any expansion runs (linear
/// in the number of distinct nodes of e; shared subexpressions are read once).
struct Expansion {
  /// An upper bound on the number of terms of e.expand(), also covering every subexpression that
  /// expand() expands on its own (denominators, bases of non-integer powers, exponents) and the
  /// arguments of functions. Saturates at +infinity.
  double terms = 0;
  /// The size of what expand() builds: the factors of every term, summed over the result and
  /// over the expansions it runs on its own. The cost of an expansion is its terms times their
  /// size, so this, not the number of terms, is what the budget holds. Saturates at +infinity.
  double factors = 0;
};
Expansion predict_expansion(const GiNaC::ex& e);

/// predict_expansion(e).terms.
double expanded_terms(const GiNaC::ex& e);

/// What normal() would build: the expanded numerator and denominator of e over a common
/// denominator (a/b + c/d → (a·d + c·b)/(b·d), powers of both, negative powers swapped), their
/// terms and factors summed. An upper bound: normal() cancels common factors. Saturates.
Expansion predict_common_denominator(const GiNaC::ex& e);

/// Number of terms of e as it stands (1 unless e is a sum).
std::size_t terms(const GiNaC::ex& e);

/// Number of nodes of e's tree: a measure of how much there is to read or print.
std::size_t node_count(const GiNaC::ex& e);

/// e.expand(), refused with WorkLimitExceeded before it runs when the prediction exceeds
/// kMaxExpandedTerms terms or kMaxExpandedFactors factors.
GiNaC::ex expand(const GiNaC::ex& e);

/// True when e (already expanded) is small and shallow enough for normal(), and its
/// common-denominator form small enough (kMaxCommonDenominatorFactors).
bool worth_simplifying(const GiNaC::ex& e);

/// True when e (already expanded) is small and shallow enough for sin² + cos² = 1.
bool worth_trigonometric_simplification(const GiNaC::ex& e);

/// e.normal() when worth_simplifying(e), else e unchanged (already a valid form of the value).
GiNaC::ex normal(const GiNaC::ex& e);

/// Whether e is identically zero. Exact (expand, then normal) below the simplification threshold;
/// above it, e is zero when its expansion is, and nonzero when it is nonzero at one of a few
/// fixed sample points of its symbols (Schwartz–Zippel: a nonzero rational function vanishes at
/// a generic point with probability zero): vanishes_at_sample_points with the intermediates as
/// symbols (zero_test.hpp). Deterministic: the points are fixed.
bool is_zero(const GiNaC::ex& e);

}  // namespace nhc::work_budget
