#pragma once
/// \file symbolic_policy.hpp
/// \brief Every tuning threshold of the symbolic work in one place: where structure is kept
/// (intermediates), what is simplified, how much one expansion may build, and how a zero is
/// recognised. Why each value, with the measurements that chose it: docs/intermediates.md,
/// "The thresholds". The processor-time limit of the whole work is work_stage.hpp's.

#include <cstddef>

namespace nhc {

// Intermediates (intermediate.hpp).

/// A derivative or total derivative of an intermediate with fewer nodes than this is kept as
/// an expression; at or above, it becomes an intermediate itself.
inline constexpr int kInlineBelowNodes = 8;
/// A definition whose substituted value has fewer nodes than this…
inline constexpr int kSubstituteDefinitionBelowNodes = 40;
/// …and at most this many terms expanded is substituted rather than kept.
inline constexpr double kSubstituteDefinitionMaxTerms = 16;
/// A kept definition's value is simplified (simplify_expression) when its expansion has at
/// most this many terms (intermediates counted as symbols); partials and total derivatives never.
inline constexpr double kSimplifyIntermediateMaxTerms = 200;
/// An expression over intermediates whose substituted form has fewer nodes than this (and at
/// most kSimplifyIntermediateMaxTerms terms expanded) is simplified in its substituted form.
inline constexpr int kSubstituteIntoExpressionBelowNodes = 150;

// Zero tests (zero_test.hpp, work_budget::is_zero).

/// The number of fixed sample points a zero test evaluates at.
inline constexpr unsigned kZeroTestPoints = 3;
/// A value is zero at a sample point when it is below this, relative to its largest term (at
/// least 1).
inline constexpr double kZeroTolerance = 1e-9;

}  // namespace nhc

namespace nhc::work_budget {

// The work budget (work_budget.hpp): refusal limits of expansion, thresholds of simplification.

/// Largest number of terms one expansion may produce.
inline constexpr double kMaxExpandedTerms = 1e5;
/// Largest size (factors over all terms and inner expansions, predict_expansion) one expansion
/// may build.
inline constexpr double kMaxExpandedFactors = 2e6;
/// Largest expanded sum that common denominators (normal()) and trigonometric simplification
/// are applied to.
inline constexpr std::size_t kMaxSimplifiedTerms = 2000;
/// Largest common-denominator form (predict_common_denominator, in factors) that normal() is
/// applied to: past it the expression is kept expanded.
inline constexpr double kMaxCommonDenominatorFactors = 1e5;
/// Largest expanded sum that sin² + cos² = 1 is applied to.
inline constexpr std::size_t kMaxTrigonometricTerms = 20000;
/// Deepest nesting of functions (sin(sin(…))) that normal() and sin² + cos² = 1 are applied to.
inline constexpr std::size_t kMaxSimplifiedNesting = 12;

}  // namespace nhc::work_budget
