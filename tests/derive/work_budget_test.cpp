// The predictions of the work budget (codegen/nhc/expr/work_budget.hpp) against GiNaC's
// own expansion of small cases and the multinomial count C(n+k−1, k−1), and the refusals before
// an expansion runs.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/work_budget.hpp"
#include "nhc/expr/zero_test.hpp"

using GiNaC::ex;
using GiNaC::symbol;

namespace {

std::vector<symbol> symbols(const std::string& stem, int n) {
  std::vector<symbol> out;
  for (int k = 0; k < n; ++k) out.emplace_back(stem + std::to_string(k));
  return out;
}

ex sum_of(const std::vector<symbol>& s) {
  ex sum = 0;
  for (const symbol& x : s) sum += x;
  return sum;
}

/// Factors of an expanded expression: each term's factors (numeric coefficients not counted).
double factors_of(const ex& e) {
  const auto term_factors = [](const ex& t) {
    if (!GiNaC::is_exactly_a<GiNaC::mul>(t)) return GiNaC::is_a<GiNaC::numeric>(t) ? 0.0 : 1.0;
    double n = 0;
    for (const ex& f : t) n += GiNaC::is_a<GiNaC::numeric>(f) ? 0 : 1;
    return n;
  };
  if (!GiNaC::is_exactly_a<GiNaC::add>(e)) return term_factors(e);
  double n = 0;
  for (const ex& t : e) n += term_factors(t);
  return n;
}

double binomial(double n, double k) {
  double b = 1;
  for (double j = 1; j <= k; ++j) b *= (n - k + j) / j;
  return b;
}

}  // namespace

TEST_CASE("a power n of a k-term sum predicts C(n+k-1, k-1) terms, exactly GiNaC's", "[derive][budget]") {
  for (int k : {2, 3, 5})
    for (int n : {1, 2, 4, 7}) {
      const ex e = GiNaC::pow(sum_of(symbols("a", k)), n);
      const nhc::work_budget::Expansion p = nhc::work_budget::predict_expansion(e);
      const ex expanded = e.expand();
      CHECK(p.terms == Approx(binomial(n + k - 1, k - 1)));
      CHECK(p.terms == static_cast<double>(nhc::work_budget::terms(expanded)));
      CHECK(p.factors >= factors_of(expanded));
      CHECK(nhc::work_budget::expand(e).is_equal(expanded));
    }
}

TEST_CASE("products multiply the terms and add the sizes of their terms", "[derive][budget]") {
  const auto a = symbols("a", 2), b = symbols("b", 3), c = symbols("c", 4);
  const ex e = sum_of(a) * sum_of(b) * GiNaC::pow(sum_of(c), 2) * a[0];
  const nhc::work_budget::Expansion p = nhc::work_budget::predict_expansion(e);
  const ex expanded = e.expand();
  CHECK(p.terms == Approx(2 * 3 * 10));
  CHECK(p.terms >= static_cast<double>(nhc::work_budget::terms(expanded)));
  CHECK(p.factors >= factors_of(expanded));
  CHECK(p.factors <= 2 * factors_of(expanded));
}

TEST_CASE("a negative power predicts the expansion of its denominator", "[derive][budget]") {
  const auto a = symbols("a", 3);
  const symbol x("x");
  const ex e = GiNaC::pow(sum_of(a), -4) * (x + 1);
  const nhc::work_budget::Expansion p = nhc::work_budget::predict_expansion(e);
  CHECK(p.terms == Approx(binomial(6, 2)));  // (a0 + a1 + a2)^4 in the denominator
  CHECK(p.factors >= factors_of(GiNaC::pow(sum_of(a), 4).expand()));
}

TEST_CASE("definitions that square the previous one are predicted in linear time and saturate", "[derive][budget]") {
  // d_k = d_{k-1}^2 + x, 500 deep: a tree of 2^500 paths, 1000 distinct nodes.
  const symbol x("x"), v("v");
  ex d = x + v;
  for (int k = 0; k < 500; ++k) d = GiNaC::pow(d, 2) + x;
  const nhc::work_budget::Expansion p = nhc::work_budget::predict_expansion(d);
  CHECK(std::isinf(p.terms));
  CHECK(std::isinf(p.factors));
  CHECK_THROWS_AS(nhc::work_budget::expand(d), nhc::WorkLimitExceeded);
}

TEST_CASE("an expansion of few terms but many factors is refused before it runs", "[derive][budget]") {
  // (b0 + … + b5)^17: 26,334 terms (under 10^5), each also carrying the 80 factors of the product.
  ex product = 1;
  for (const symbol& s : symbols("c", 80)) product *= s;
  const ex e = product * GiNaC::pow(sum_of(symbols("b", 6)), 17);
  const nhc::work_budget::Expansion p = nhc::work_budget::predict_expansion(e);
  CHECK(p.terms == Approx(binomial(22, 5)));
  CHECK(p.terms < nhc::work_budget::kMaxExpandedTerms);
  CHECK(p.factors > nhc::work_budget::kMaxExpandedFactors);
  CHECK_THROWS_WITH(nhc::work_budget::expand(e),
                    Catch::Contains("factors in") && Catch::Contains("terms (the limit is"));
}

TEST_CASE("the one zero test: through intermediates or with them as symbols, rounding relative to the terms",
          "[derive][budget]") {
  const GiNaC::symbol x("x"), y("y");
  // s = sin(x) as a named intermediate: s^2 + cos(x)^2 - 1 vanishes as a function, not as a form.
  const GiNaC::ex s = nhc::Intermediate("s", "s", GiNaC::sin(x));
  const GiNaC::ex hidden = GiNaC::pow(s, 2) + GiNaC::pow(GiNaC::cos(x), 2) - 1;
  CHECK(nhc::vanishes_at_sample_points(hidden));
  CHECK_FALSE(nhc::vanishes_at_sample_points(hidden, {}, nhc::IntermediateValues::as_symbols));
  // Terms of 1e12 that cancel leave rounding far above 1e-9 in absolute terms, not relative ones;
  // a small term on its own is not rounding.
  const GiNaC::ex cancelling = 1e12 * GiNaC::pow(GiNaC::sin(x), 2) + 1e12 * GiNaC::pow(GiNaC::cos(x), 2) - 1e12;
  CHECK(nhc::vanishes_at_sample_points(cancelling, {}, nhc::IntermediateValues::as_symbols));
  CHECK_FALSE(nhc::vanishes_at_sample_points(1e-6 * x * y, {}, nhc::IntermediateValues::as_symbols));
  // A pole at a sample point is not evidence of zero.
  CHECK_FALSE(nhc::vanishes_at_sample_points(y / (x - 1), {{x, 1}}));
}
