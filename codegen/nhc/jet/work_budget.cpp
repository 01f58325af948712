#include "nhc/jet/work_budget.hpp"

#include "nhc/runtime/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>
#include <limits>
#include <sstream>

#include "nhc/long_work.hpp"

namespace nhc::work_budget {

namespace {

using GiNaC::ex;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// C(n + k − 1, k), the number of monomials of degree k in n terms, as a product of k factors.
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

/// Terms of e.expand() at e's own level; what expand() expands separately goes into `inner`.
double outer_terms(const ex& e, double& inner) {
  if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
    double sum = 0;
    for (std::size_t k = 0; k < e.nops(); ++k) sum += outer_terms(e.op(k), inner);
    return sum;
  }
  if (GiNaC::is_exactly_a<GiNaC::mul>(e)) {
    double product = 1;
    for (std::size_t k = 0; k < e.nops(); ++k) product *= outer_terms(e.op(k), inner);
    return std::isnan(product) ? kInfinity : product;
  }
  if (GiNaC::is_exactly_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
      GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_integer()) {
    // (a + b)^k multiplies out; (a + b)^−k expands its denominator (a + b)^k alone, and stays
    // one term in the sum around it.
    const GiNaC::numeric k = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
    const double n = outer_terms(e.op(0), inner);
    const double bound = power_terms(n, std::fabs(k.to_double()));
    if (k.is_positive()) return bound;
    inner = std::max(inner, bound);
    return 1;
  }
  for (std::size_t k = 0; k < e.nops(); ++k) inner = std::max(inner, outer_terms(e.op(k), inner));
  return 1;
}

std::string count_text(double n) {
  if (std::isinf(n)) return "beyond 10^300";
  return runtime::number_text(n, 2);
}

}  // namespace

double expanded_terms(const ex& e) {
  double inner = 0;
  const double outer = outer_terms(e, inner);
  return std::max(outer, inner);
}

std::size_t terms(const ex& e) { return GiNaC::is_exactly_a<GiNaC::add>(e) ? e.nops() : 1; }

std::size_t node_count(const ex& e) {
  std::size_t n = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) ++n;
  return n;
}

ex expand(const ex& e) {
  check_for_stop();  // the pipeline's expensive operations all pass here or through normal()
  const double bound = expanded_terms(e);
  if (bound > kMaxExpandedTerms)
    throw WorkLimitExceeded("expanding an expression would give up to " + count_text(bound) +
                            " terms (the limit is " + count_text(kMaxExpandedTerms) + ")");
  ex r = e.expand();
  return r;
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
  return terms(e) <= kMaxSimplifiedTerms && function_nesting(e) <= kMaxSimplifiedNesting;
}

bool worth_trigonometric_simplification(const ex& e) {
  return terms(e) <= kMaxTrigonometricTerms && function_nesting(e) <= kMaxSimplifiedNesting;
}

ex normal(const ex& e) {
  check_for_stop();
  return worth_simplifying(e) ? e.normal() : e;
}

namespace {

/// A fixed point for the symbols of e: values in (0.3, 1.3), away from 0 (no division by zero
/// in q^−k) and from the integers, different for each `seed`.
GiNaC::exmap sample_point(const ex& e, unsigned seed) {
  GiNaC::exmap point;
  unsigned k = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it) && point.find(*it) == point.end())
      point[*it] = 0.3 + std::fmod(0.6180339887498949 * (1 + k++) + 0.4142135623730950 * seed, 1.0);
  return point;
}

/// e at `point`; NaN when it is not a finite real number there (a pole, a branch cut).
double value_at(const ex& e, const GiNaC::exmap& point) {
  try {
    const ex value = GiNaC::evalf(e.subs(point, GiNaC::subs_options::no_pattern));
    if (!GiNaC::is_a<GiNaC::numeric>(value)) return std::numeric_limits<double>::quiet_NaN();
    const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(value);
    if (!n.is_real()) return std::numeric_limits<double>::quiet_NaN();
    return n.to_double();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace

bool is_zero(const ex& e) {
  if (e.is_zero()) return true;
  check_for_stop();
  const ex expanded = nhc::work_budget::expand(e);
  if (expanded.is_zero()) return true;
  if (worth_simplifying(expanded)) return expanded.normal().is_zero();
  // Large: numeric evidence. The magnitude of the terms sets what rounding can leave behind.
  for (unsigned seed = 0; seed < 3; ++seed) {
    const GiNaC::exmap point = sample_point(expanded, seed);
    double value = 0, scale = 0;
    for (std::size_t k = 0; k < expanded.nops(); ++k) {
      const double term = value_at(expanded.op(k), point);
      value += term;
      scale = std::max(scale, std::fabs(term));
    }
    if (std::isnan(value) || std::isinf(value)) continue;
    if (std::fabs(value) > 1e-9 * std::max(scale, 1.0)) return false;
  }
  return true;
}

}  // namespace nhc::work_budget
