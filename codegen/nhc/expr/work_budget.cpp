#include "nhc/expr/work_budget.hpp"

#include "nhc/base/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>
#include <limits>
#include <sstream>

#include "nhc/long_work.hpp"
#include "nhc/expr/zero_test.hpp"

namespace nhc::work_budget {

namespace {

using GiNaC::ex;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// C(n + k − 1, k), the number of monomials of degree k in n terms, as a product of k factors.
/// Saturates at +infinity (never wraps: doubles).
double power_terms(double n, double k) {
  if (n <= 1) return 1;
  if (k > 1e6 || std::isinf(n)) return kInfinity;
  double bound = 1;
  for (double j = 1; j <= k; ++j) {
    bound *= (n - 1 + j) / j;
    if (bound > 1e300) return kInfinity;
  }
  return bound;
}

/// The sequence of a sum or product read in place: `seq` and `overall_coeff` are protected
/// members of GiNaC::expairseq, and op(k) would build a new product (or power) for every pair,
/// an allocation per factor for each prediction. A pointer to a member named through a derived
/// class applies to any expairseq; the class is never instantiated.
struct SequenceOf : GiNaC::expairseq {
  static const GiNaC::epvector& pairs(const GiNaC::expairseq& e) { return e.*(&SequenceOf::seq); }
  static const ex& coefficient(const GiNaC::expairseq& e) { return e.*(&SequenceOf::overall_coeff); }
};

/// The prediction of e.expand() for one node of the tree.
struct Prediction {
  double terms = 1;        ///< terms of the result at this node's level (a bound)
  double factors = 1;      ///< factors over all those terms (each term's factor count summed)
  double inner_terms = 0;  ///< the largest expansion expand() runs on its own inside (denominators, bases)
  double inner_work = 0;   ///< factors of all those inner expansions, summed
};

/// Adds what sits inside a node (`inner`) to `into`.
void absorb(Prediction& into, const Prediction& inner) {
  into.inner_terms = std::max(into.inner_terms, inner.inner_terms);
  into.inner_work += inner.inner_work;
}

/// Memoised on the node: a tree whose subexpressions are shared (definitions squaring the
/// previous one) is read once per distinct node, not once per path.
class Predictor {
 public:
  const Prediction& of(const ex& e) {
    const GiNaC::basic* node = &GiNaC::ex_to<GiNaC::basic>(e);
    const auto found = memo_.find(node);
    if (found != memo_.end()) return found->second;
    const Prediction p = compute(e);
    return memo_.emplace(node, p).first->second;
  }

 private:
  Prediction compute(const ex& e) {
    Prediction p;
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      p.factors = 0;  // a coefficient, not a factor
      return p;
    }
    if (GiNaC::is_a<GiNaC::symbol>(e)) return p;  // also a named intermediate: one factor
    if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
      const auto& sum = GiNaC::ex_to<GiNaC::expairseq>(e);
      p.terms = p.factors = 0;
      for (const GiNaC::expair& pair : SequenceOf::pairs(sum)) {
        const Prediction& t = of(pair.rest);  // the numeric coefficient adds no term
        p.terms += t.terms;
        p.factors += t.factors;
        absorb(p, t);
      }
      if (!SequenceOf::coefficient(sum).is_zero()) p.terms += 1;
      return p;
    }
    if (GiNaC::is_exactly_a<GiNaC::mul>(e)) {
      // Every term of the product takes one term of each factor: terms multiply, and a term's
      // factor count is the sum of the factors' average term sizes.
      double per_term = 0;
      for (const GiNaC::expair& pair : SequenceOf::pairs(GiNaC::ex_to<GiNaC::expairseq>(e))) {
        const Prediction f = power_of(pair.rest, pair.coeff);
        p.terms *= f.terms;
        per_term += f.terms > 0 ? f.factors / f.terms : 0;
        absorb(p, f);
      }
      if (std::isnan(p.terms)) p.terms = kInfinity;
      p.factors = saturated(p.terms * per_term);
      return p;
    }
    if (GiNaC::is_exactly_a<GiNaC::power>(e)) return power_of(e.op(0), e.op(1));
    // A function and anything else: one factor. expand() leaves function arguments as they are
    // (without expand_options::expand_function_args); their terms still count towards the bound
    // of expanded_terms (its callers decide with it whether a definition is substituted).
    for (std::size_t k = 0; k < e.nops(); ++k) {
      const Prediction& a = of(e.op(k));
      absorb(p, a);
      p.inner_terms = std::max(p.inner_terms, a.terms);
    }
    return p;
  }

  /// base^exponent, as a power node or as one pair of a product.
  Prediction power_of(const ex& base, const ex& exponent) {
    const Prediction& b = of(base);
    if (GiNaC::is_a<GiNaC::numeric>(exponent) && exponent.is_equal(GiNaC::ex(1))) return b;
    Prediction p;
    absorb(p, b);
    if (GiNaC::is_a<GiNaC::numeric>(exponent) && GiNaC::ex_to<GiNaC::numeric>(exponent).is_integer()) {
      // (a + b)^k multiplies out: C(n + k − 1, k) terms, each a product of k of the base's terms
      // (at most as many distinct factors as the whole base has); (a + b)^−k expands its
      // denominator (a + b)^k alone, and stays one factor of the product around it.
      const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
      const double power = std::fabs(k.to_double());
      const double terms = power_terms(b.terms, power);
      const double per_term = b.terms > 1 ? std::min(power * b.factors / b.terms, b.factors) : b.factors;
      if (k.is_positive()) {
        p.terms = terms;
        p.factors = saturated(terms * per_term);
        return p;
      }
      p.inner_terms = std::max(p.inner_terms, terms);
      if (b.terms > 1) p.inner_work += saturated(terms * per_term);
      p.factors = b.terms > 1 ? 1 : b.factors;
      return p;
    }
    // A non-integer or symbolic exponent: expand() expands base and exponent on their own.
    const Prediction& x = of(exponent);
    absorb(p, x);
    p.inner_terms = std::max({p.inner_terms, b.terms, x.terms});
    p.inner_work += b.factors + x.factors;
    return p;
  }

  static double saturated(double x) { return std::isnan(x) || x > 1e300 ? kInfinity : x; }

  std::unordered_map<const GiNaC::basic*, Prediction> memo_;
};

/// Terms and factors of one expanded polynomial (numerator or denominator).
struct Polynomial {
  double terms = 1, factors = 0;
};

Polynomial times(const Polynomial& a, const Polynomial& b) {
  const double terms = a.terms * b.terms;
  const double per_term = (a.terms > 0 ? a.factors / a.terms : 0) + (b.terms > 0 ? b.factors / b.terms : 0);
  return {std::isnan(terms) ? kInfinity : terms, std::isnan(terms * per_term) ? kInfinity : terms * per_term};
}

Polynomial raised(const Polynomial& a, double k) {
  if (a.terms <= 1) return {1, a.factors};
  const double terms = power_terms(a.terms, k);
  const double factors = terms * std::min(k * a.factors / a.terms, a.factors);
  return {terms, std::isnan(factors) ? kInfinity : factors};
}

/// The common-denominator form normal() builds, numerator over denominator, both expanded:
/// a sum a/b + c/d becomes (a·(l/b) + c·(l/d))/l over the least common multiple l of the
/// denominators (the same base counted once, at its highest power), a power of a fraction the
/// powers of both, a negative power swaps them. An upper bound (GiNaC also cancels common factors
/// by gcd, which only shrinks the result, and costs more the larger these are). Memoised on the
/// node like Predictor.
class FractionPredictor {
 public:
  /// A denominator: its bases (by node) with their exponents and expanded sizes.
  using Denominator = std::map<const GiNaC::basic*, std::pair<double, Polynomial>>;
  struct Fraction {
    Polynomial numerator;
    Denominator denominator;
  };

  const Fraction& of(const ex& e) {
    const GiNaC::basic* node = &GiNaC::ex_to<GiNaC::basic>(e);
    const auto found = memo_.find(node);
    if (found != memo_.end()) return found->second;
    Fraction f = compute(e);
    return memo_.emplace(node, std::move(f)).first->second;
  }

  static Polynomial size_of(const Denominator& d, const Denominator* divided_by = nullptr) {
    Polynomial p{1, 0};
    for (const auto& [base, entry] : d) {
      double exponent = entry.first;
      if (divided_by != nullptr) {
        const auto other = divided_by->find(base);
        if (other != divided_by->end()) exponent -= other->second.first;
      }
      if (exponent > 0) p = times(p, raised(entry.second, exponent));
    }
    return p;
  }

 private:
  Fraction compute(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return {{1, 0}, {}};
    if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
      const auto& sum = GiNaC::ex_to<GiNaC::expairseq>(e);
      Fraction result{{0, 0}, {}};
      for (const GiNaC::expair& pair : SequenceOf::pairs(sum))
        for (const auto& [base, entry] : of(pair.rest).denominator) {
          auto& at = result.denominator[base];
          at = {std::max(at.first, entry.first), entry.second};
        }
      const auto add_term = [&](const Polynomial& numerator, const Denominator* own) {
        const Polynomial t = times(numerator, size_of(result.denominator, own));
        result.numerator = {result.numerator.terms + t.terms, result.numerator.factors + t.factors};
      };
      for (const GiNaC::expair& pair : SequenceOf::pairs(sum)) {
        const Fraction& t = of(pair.rest);
        add_term(t.numerator, &t.denominator);
      }
      if (!SequenceOf::coefficient(sum).is_zero()) add_term({1, 0}, nullptr);
      return result;
    }
    if (GiNaC::is_exactly_a<GiNaC::mul>(e)) {
      Fraction product{{1, 0}, {}};
      for (const GiNaC::expair& pair : SequenceOf::pairs(GiNaC::ex_to<GiNaC::expairseq>(e))) {
        const Fraction f = power_of(pair.rest, pair.coeff);
        product.numerator = times(product.numerator, f.numerator);
        for (const auto& [base, entry] : f.denominator) {
          auto& at = product.denominator[base];
          at = {at.first + entry.first, entry.second};
        }
      }
      return product;
    }
    if (GiNaC::is_exactly_a<GiNaC::power>(e)) return power_of(e.op(0), e.op(1));
    return {{1, 1}, {}};  // a symbol, a function (normal() takes it as a whole): one factor
  }

  Fraction power_of(const ex& base, const ex& exponent) {
    if (!GiNaC::is_a<GiNaC::numeric>(exponent) || !GiNaC::ex_to<GiNaC::numeric>(exponent).is_integer())
      return {{1, 1}, {}};  // a non-integer power: one factor of its own
    const Fraction& b = of(base);
    const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
    const double power = std::fabs(k.to_double());
    Fraction f;
    if (k.is_positive()) {
      f.numerator = raised(b.numerator, power);
      for (const auto& [node, entry] : b.denominator) f.denominator[node] = {entry.first * power, entry.second};
    } else {
      // (n/d)^−k = d^k / n^k: the base's numerator becomes one denominator base, its own
      // denominator moves up.
      f.numerator = raised(size_of(b.denominator), power);
      f.denominator[&GiNaC::ex_to<GiNaC::basic>(base)] = {power, b.numerator};
    }
    return f;
  }

  std::unordered_map<const GiNaC::basic*, Fraction> memo_;
};

std::string count_text(double n) {
  if (std::isinf(n)) return "beyond 10^300";
  return base::number_text(n, 2);
}

}  // namespace

Expansion predict_expansion(const ex& e) {
  Predictor predictor;
  const Prediction& p = predictor.of(e);
  return {std::max(p.terms, p.inner_terms), std::min(p.factors + p.inner_work, kInfinity)};
}

double expanded_terms(const ex& e) { return predict_expansion(e).terms; }

Expansion predict_common_denominator(const ex& e) {
  FractionPredictor predictor;
  const FractionPredictor::Fraction& f = predictor.of(e);
  const Polynomial denominator = FractionPredictor::size_of(f.denominator);
  const double terms = f.numerator.terms + denominator.terms, factors = f.numerator.factors + denominator.factors;
  return {std::isnan(terms) ? kInfinity : std::min(terms, kInfinity),
          std::isnan(factors) ? kInfinity : std::min(factors, kInfinity)};
}

std::size_t terms(const ex& e) { return GiNaC::is_exactly_a<GiNaC::add>(e) ? e.nops() : 1; }

std::size_t node_count(const ex& e) {
  std::size_t n = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) ++n;
  return n;
}

ex expand(const ex& e) {
  check_for_stop();  // the pipeline's expensive operations all pass here or through normal()
  const Expansion predicted = predict_expansion(e);
  if (predicted.terms > kMaxExpandedTerms)
    throw WorkLimitExceeded("expanding an expression would give up to " + count_text(predicted.terms) +
                            " terms (the limit is " + count_text(kMaxExpandedTerms) + ")");
  if (predicted.factors > kMaxExpandedFactors)
    throw WorkLimitExceeded("expanding an expression would build about " + count_text(predicted.factors) +
                            " factors in " + count_text(predicted.terms) + " terms (the limit is " +
                            count_text(kMaxExpandedFactors) + " factors)");
  return e.expand();
}

std::size_t function_nesting(const ex& e, std::size_t limit) {
  // Iterative, with the depth of each pending node: a user's chain of definitions may nest
  // thousands deep, more than the call stack holds. Shared subtrees are visited once per depth.
  std::vector<std::pair<ex, std::size_t>> pending{{e, 0}};
  std::map<ex, std::size_t, GiNaC::ex_is_less> seen;  // node → deepest depth visited at
  std::size_t deepest = 0;
  while (!pending.empty()) {
    auto [node, depth] = pending.back();
    pending.pop_back();
    if (GiNaC::is_a<GiNaC::function>(node)) ++depth;
    deepest = std::max(deepest, depth);
    if (deepest > limit) return deepest;
    const auto it = seen.find(node);
    if (it != seen.end() && it->second >= depth) continue;
    seen[node] = depth;
    for (std::size_t k = 0; k < node.nops(); ++k) pending.emplace_back(node.op(k), depth);
  }
  return deepest;
}

bool worth_simplifying(const ex& e) {
  return terms(e) <= kMaxSimplifiedTerms && function_nesting(e) <= kMaxSimplifiedNesting &&
         predict_common_denominator(e).factors <= kMaxCommonDenominatorFactors;
}

bool worth_trigonometric_simplification(const ex& e) {
  return terms(e) <= kMaxTrigonometricTerms && function_nesting(e) <= kMaxSimplifiedNesting;
}

ex normal(const ex& e) {
  check_for_stop();
  return worth_simplifying(e) ? e.normal() : e;
}

bool is_zero(const ex& e) {
  if (e.is_zero()) return true;
  check_for_stop();
  const ex expanded = nhc::work_budget::expand(e);
  if (expanded.is_zero()) return true;
  if (worth_simplifying(expanded)) return expanded.normal().is_zero();
  // Large: numeric evidence, the intermediates as symbols (the form decides, as above). The
  // magnitude of the terms sets what rounding can leave behind.
  return vanishes_at_sample_points(expanded, {}, IntermediateValues::as_symbols);
}

}  // namespace nhc::work_budget
