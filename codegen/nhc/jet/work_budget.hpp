#pragma once
/// \file work_budget.hpp
/// \brief The work budget of the symbolic pipeline: every operation whose cost can grow without
/// bound in the size of its input goes through here, and this is the one place that decides how
/// much is too much.
///
/// Two kinds of limit:
/// - a *refusal* limit for work the pipeline cannot do without: expansion. Its result size is
///   bounded from the structure before any work is done (sums add, products multiply, an integer
///   power k of an n-term sum has at most C(n+k−1, k) terms, a negative one as many in its
///   denominator); past kMaxExpandedTerms the operation throws WorkLimitExceeded, which the
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

namespace nhc::work_budget {

/// Largest number of terms one expansion may produce. Expanding is linear in its result at best
/// (a product of three 21-term sums, 9,261 terms, takes about 0.1 s; a sum of 10^5 terms about a
/// second and hundreds of megabytes once differentiated). The bound is loose for sums of
/// trigonometric products; the largest bound in the examples is the Whipple bicycle's, 36,883
/// (6,044 terms after expansion).
inline constexpr double kMaxExpandedTerms = 1e5;
/// Largest expanded sum that common denominators (normal()) and trigonometric simplification
/// are applied to. normal() is quadratic or worse in the number of terms (a gcd per pair of
/// denominators): 9,261 terms over negative powers ran for minutes. The largest expression whose
/// common-denominator form the examples use has 816 terms (the Whipple bicycle).
inline constexpr std::size_t kMaxSimplifiedTerms = 2000;
/// Largest expanded sum that sin² + cos² = 1 is applied to: a substitution and an expansion
/// (bounded by kMaxExpandedTerms), near linear in the terms. The Whipple bicycle's equations need
/// it up to 6,044 terms: its rear-wheel angle cancels from them only through the identity.
inline constexpr std::size_t kMaxTrigonometricTerms = 20000;
/// Deepest nesting of functions (sin(sin(…))) that normal() and sin² + cos² = 1 are applied to:
/// both work through every function argument, each at every level, so their cost grows with a
/// power of the depth (a chain of 200 definitions d_k = sin(d_{k-1}) took 50 s in normal()).
/// Mechanics nests a handful deep (a sqrt of a sum of products of sines).
inline constexpr std::size_t kMaxSimplifiedNesting = 12;

/// The deepest nesting of function calls in e (0 for a polynomial, 1 for sin(x), 2 for
/// sqrt(sin(x)), …); stops counting past `limit`.
std::size_t function_nesting(const GiNaC::ex& e, std::size_t limit = kMaxSimplifiedNesting + 1);

/// An upper bound on the number of terms of e.expand(), also covering every subexpression that
/// expand() expands on its own (function arguments, bases of non-integer powers, exponents).
/// Saturates at +infinity.
double expanded_terms(const GiNaC::ex& e);

/// Number of terms of e as it stands (1 unless e is a sum).
std::size_t terms(const GiNaC::ex& e);

/// Number of nodes of e's tree: a measure of how much there is to read or print.
std::size_t node_count(const GiNaC::ex& e);

/// e.expand(), refused with WorkLimitExceeded when expanded_terms(e) > kMaxExpandedTerms.
GiNaC::ex expand(const GiNaC::ex& e);

/// True when e (already expanded) is small and shallow enough for normal().
bool worth_simplifying(const GiNaC::ex& e);

/// True when e (already expanded) is small and shallow enough for sin² + cos² = 1.
bool worth_trigonometric_simplification(const GiNaC::ex& e);

/// e.normal() when worth_simplifying(e), else e unchanged (already a valid form of the value).
GiNaC::ex normal(const GiNaC::ex& e);

/// Whether e is identically zero. Exact (expand, then normal) below the simplification threshold;
/// above it, e is zero when its expansion is, and nonzero when it is nonzero at one of a few
/// fixed sample points of its symbols (Schwartz–Zippel: a nonzero rational function vanishes at
/// a generic point with probability zero). Deterministic: the points are fixed.
bool is_zero(const GiNaC::ex& e);

}  // namespace nhc::work_budget
