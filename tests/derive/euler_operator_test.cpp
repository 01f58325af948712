// The Euler operator built by integration by parts (the paper's way) against the closed formula,
// and the variation identity, paper eq. (12), for a generic constraint of order m = 1, 2, 3.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <random>
#include <vector>

#include "nhc/derive/euler_operator.hpp"
#include "nhc/expr/jet_space.hpp"
#include "variation_identity.hpp"

using GiNaC::ex;
using nhc::JetSpace;
using nhc::VariableKind;

namespace {

bool same(const ex& a, const ex& b) {
  const ex d = (a - b).expand();
  return d.is_zero() || d.normal().is_zero();
}

/// Random expressions in the jet symbols up to a given order: sums of monomials with small
/// integer coefficients, times occasional sin/cos/exp of a jet symbol. Fixed seed.
class RandomJetExpression {
 public:
  RandomJetExpression(const JetSpace& jet, unsigned seed) : jet_(jet), rng_(seed) {}

  ex make(int max_order, bool with_multipliers) {
    ex sum = 0;
    const int terms = pick(1, 4);
    for (int t = 0; t < terms; ++t) {
      ex term = pick(-3, 3);
      if (term.is_zero()) term = 1;
      const int factors = pick(1, 3);
      for (int f = 0; f < factors; ++f) {
        const ex s = symbol(max_order, with_multipliers);
        switch (pick(0, 5)) {
          case 0:
            term *= GiNaC::sin(s);
            break;
          case 1:
            term *= GiNaC::cos(s);
            break;
          case 2:
            term *= GiNaC::exp(s / 2);
            break;
          default:
            term *= GiNaC::pow(s, pick(1, 3));
            break;
        }
      }
      if (pick(0, 3) == 0) term *= jet_.time();
      sum += term;
    }
    return sum;
  }

 private:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  ex symbol(int max_order, bool with_multipliers) {
    if (with_multipliers && jet_.multiplier_count() > 0 && pick(0, 4) == 0)
      return jet_.lambda(pick(0, jet_.multiplier_count() - 1), pick(0, 2));
    return jet_.q(pick(0, jet_.coordinate_count() - 1), pick(0, max_order));
  }
  const JetSpace& jet_;
  std::mt19937 rng_;
};

}  // namespace

TEST_CASE("IBP-built Euler operator equals the closed formula on random L and f", "[derive][euler]") {
  const JetSpace jet({"q1", "q2", "q3"}, 2, {"c"});
  RandomJetExpression random(jet, 20130501u);
  int checked = 0;
  for (int order = 0; order <= 4; ++order) {
    for (int sample = 0; sample < 6; ++sample) {
      const ex F = random.make(order, /*with_multipliers=*/sample % 2 == 1) * jet.parameter(0);
      INFO("order " << order << ", F = " << F);
      const auto by_parts = nhc::euler_operator(F, jet);
      const auto closed = nhc::euler_operator_closed_form(F, jet);
      REQUIRE(by_parts.size() == 3);
      REQUIRE(closed.size() == 3);
      for (int i = 0; i < 3; ++i) CHECK(same(by_parts[i], closed[i]));
      ++checked;
    }
  }
  CHECK(checked == 30);
}

TEST_CASE("Euler operator: known cases", "[derive][euler]") {
  const JetSpace jet({"q"}, 1, {});
  const ex q = jet.q(0, 0), q1 = jet.q(0, 1), q2 = jet.q(0, 2);
  // First order: [L] = ∂L/∂q − D ∂L/∂q'.
  CHECK(same(nhc::euler_operator(q1 * q1 / 2 - q * q / 2, jet)[0], -q2 - q));
  // A total derivative has zero Euler operator: D(q q' sin q) for instance.
  CHECK(same(nhc::euler_operator(jet.total_derivative(q * q1 * GiNaC::sin(q)), jet)[0], 0));
  // Second order: E(q''^2/2) = q''''.
  CHECK(same(nhc::euler_operator(q2 * q2 / 2, jet)[0], jet.q(0, 4)));
  // The multiplier is a function of t, not a coordinate: E(λ q') = −λ'.
  CHECK(same(nhc::euler_operator(jet.lambda(0, 0) * q1, jet)[0], -jet.lambda(0, 1)));
  // Explicit time dependence is differentiated by D too: E(t q') = −1.
  CHECK(same(nhc::euler_operator(jet.time() * q1, jet)[0], -1));
}

TEST_CASE("variation identity, eq. (12): holds for m = 1", "[derive][identity]") {
  const nhc::testing::VariationIdentity identity(1);
  CHECK(identity.remainder().is_zero());
}

TEST_CASE("variation identity, eq. (12): the remainder for m = 2, 3 is pinned", "[derive][identity]") {
  // The printed identity moves D^k off the product ∂f/∂q^(k) δq as if D^k were a derivation
  // (D^k(a δq) = D^k(a) δq + a D^k(δq)); Leibniz's rule adds the cross terms
  // Σ_{k=2}^m Σ_{j=1}^{k-1} C(k,j) D^{k-j}(∂f/∂q^(k)) D^j(δq).
  for (int m = 2; m <= 3; ++m) {
    INFO("m = " << m);
    const nhc::testing::VariationIdentity identity(m);
    CHECK(!identity.remainder().is_zero());
    CHECK(same(identity.remainder(), identity.leibniz_cross_terms()));
  }
  // Spelled out for m = 2: 2 D(∂f/∂q'') D(δq).
  const nhc::testing::VariationIdentity two(2);
  const ex expected = 2 * two.total_derivative(two.partial(2)) * two.variation_derivative(1);
  CHECK(same(two.remainder(), expected));
}
