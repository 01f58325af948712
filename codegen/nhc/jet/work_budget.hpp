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

namespace nhc::work_budget {

/// Largest number of terms one expansion may produce. Expanding is linear in its result at best
/// (a product of three 21-term sums, 9,261 terms, takes about 0.1 s; a sum of 10^5 terms about a
/// second and hundreds of megabytes once differentiated). The bound is loose for sums of
/// trigonometric products; the largest bound in the examples is the Whipple bicycle's, 36,883
/// (6,044 terms after expansion).
inline constexpr double kMaxExpandedTerms = 1e5;
/// Largest size (factors over all terms and inner expansions, predict_expansion) one expansion
/// may build. GiNaC's expand() costs about a microsecond per factor it builds, and more in
/// the sorting of like terms; the largest prediction in the examples is the Whipple bicycle's
/// with its definitions substituted (`--expand`), 453,178 (54,326 built), and the issue-44
/// scenes ask for millions in one call. 2·10^6 keeps one expansion well inside the work
/// watchdog's seconds (work_stage.hpp), which bounds the sum of many smaller ones.
inline constexpr double kMaxExpandedFactors = 2e6;
/// Largest expanded sum that common denominators (normal()) and trigonometric simplification
/// are applied to. normal() is quadratic or worse in the number of terms (a gcd per pair of
/// denominators): 9,261 terms over negative powers ran for minutes. The largest expression whose
/// common-denominator form the examples use has 816 terms (the Whipple bicycle).
inline constexpr std::size_t kMaxSimplifiedTerms = 2000;
/// Largest common-denominator form (predict_common_denominator, in factors) that normal() is
/// applied to: past it the expression is kept expanded. normal() multiplies every term by the
/// other terms' denominators and takes greatest common divisors of the results, so a sum of
/// few terms over nested sums costs more than its size shows: 1/(x'+1/(y'+1/(x+1/(y+x'))))^12
/// (one term) ran for minutes in normal() (3·10^10 predicted). The largest in the examples is the
/// Whipple bicycle's with its definitions substituted, 13,199 (1,733 terms).
inline constexpr double kMaxCommonDenominatorFactors = 1e5;
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
/// a generic point with probability zero). Deterministic: the points are fixed.
bool is_zero(const GiNaC::ex& e);

}  // namespace nhc::work_budget
