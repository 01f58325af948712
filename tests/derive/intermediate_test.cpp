// Named intermediates (nhc/expr/intermediate.hpp): derivatives by the chain rule through them,
// checked against independent paths — GiNaC's derivative of the fully substituted expression
// where that is small, and central finite differences of the same quantity computed by a plain
// C++ loop where it is not (the chain d_k = d_{k-1}^2 + x, whose expansion has degree 2^24).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/jet_space.hpp"

namespace {

using GiNaC::ex;

/// The chain d0 = x' + y + 1, d_k = d_{k-1}^2 + x (k = 1 … n) over intermediates; returns d_n.
ex chain(const nhc::JetSpace& jet, int n) {
  const ex x = jet.q(0, 0), xd = jet.q(0, 1), y = jet.q(1, 0);
  ex d = nhc::Intermediate("d0", "d_0", xd + y + 1);
  for (int k = 1; k <= n; ++k) d = nhc::Intermediate("d" + std::to_string(k), "d_" + std::to_string(k), d * d + x);
  return d;
}

/// The same chain as a number: the independent path.
double chain_value(int n, double x, double xd, double y) {
  double d = xd + y + 1;
  for (int k = 1; k <= n; ++k) d = d * d + x;
  return d;
}

/// e at a point, evaluating each intermediate once in dependency order (no expansion).
double evaluate(const ex& e, const GiNaC::exmap& point) {
  GiNaC::exmap values = point;
  for (const ex& d : nhc::intermediates_in_order({e}))
    values[d] = GiNaC::ex_to<nhc::Intermediate>(d).expression().subs(values, GiNaC::subs_options::no_pattern).evalf();
  const ex value = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(value));
  return GiNaC::ex_to<GiNaC::numeric>(value).to_double();
}

nhc::JetSpace plane() { return nhc::JetSpace({"x", "y"}, 0, {"m"}); }

/// The jet space's own symbol q_i^(k) (a reference that lives as long as the space; JetSpace::q
/// returns a copy, whose ex_to would dangle).
const GiNaC::symbol& symbol_of(const nhc::JetSpace& jet, int i, int order) {
  return jet.symbol({nhc::VariableKind::coordinate, i, order});
}

}  // namespace

TEST_CASE("partial derivatives through a short chain equal those of the substituted expression", "[intermediate]") {
  const nhc::JetSpace jet = plane();
  const ex L = chain(jet, 3);
  for (const auto& [i, order] : std::vector<std::pair<int, int>>{{0, 0}, {0, 1}, {1, 0}, {1, 1}}) {
    const GiNaC::symbol& s = symbol_of(jet, i, order);
    const ex z = s;
    const ex through = nhc::expand_intermediates(L.diff(s));
    const ex substituted = nhc::expand_intermediates(L).diff(s);
    INFO(z);
    CHECK((through - substituted).expand().is_zero());
  }
  // Second derivatives too: the memoized partials are intermediates that differentiate again.
  const GiNaC::symbol& xd = symbol_of(jet, 0, 1);
  const GiNaC::symbol& x = symbol_of(jet, 0, 0);
  CHECK((nhc::expand_intermediates(L.diff(xd).diff(x)) - nhc::expand_intermediates(L).diff(xd).diff(x))
            .expand()
            .is_zero());
}

TEST_CASE("a chain of 24 definitions differentiates without expanding", "[intermediate]") {
  const nhc::JetSpace jet = plane();
  const ex L = chain(jet, 24);
  const GiNaC::symbol& x = symbol_of(jet, 0, 0);
  const GiNaC::symbol& xd = symbol_of(jet, 0, 1);
  const double px = -0.3, pxd = 0.2, py = -0.7;  // a point where the chain stays bounded
  const GiNaC::exmap point{{jet.q(0, 0), px}, {jet.q(0, 1), pxd}, {jet.q(1, 0), py}};
  const double h = 1e-6;
  const double fd_x = (chain_value(24, px + h, pxd, py) - chain_value(24, px - h, pxd, py)) / (2 * h);
  const double fd_xd = (chain_value(24, px, pxd + h, py) - chain_value(24, px, pxd - h, py)) / (2 * h);
  CHECK(evaluate(L, point) == Approx(chain_value(24, px, pxd, py)).epsilon(1e-14));
  CHECK(evaluate(L.diff(x), point) == Approx(fd_x).epsilon(1e-7));
  CHECK(evaluate(L.diff(xd), point) == Approx(fd_xd).epsilon(1e-7).margin(1e-9));  // ≈ -1.3e-8: the chain contracts
  // In proportion to the structure: one partial per link and variable, not 2^24 terms.
  CHECK(nhc::intermediates_in_order({L.diff(x), L.diff(xd)}).size() <= 3 * 25);
}

TEST_CASE("a chain of 3000 links differentiates iteratively", "[intermediate]") {
  const nhc::JetSpace jet = plane();
  const ex x = jet.q(0, 0);
  ex d = nhc::Intermediate("c0", "c_0", x);
  for (int k = 1; k <= 3000; ++k) d = nhc::Intermediate("c" + std::to_string(k), "c_" + std::to_string(k), d + x);
  // c_n = (n + 1) x: ∂c_n/∂x = n + 1, by 3000 memoized steps of the chain rule.
  CHECK(evaluate(d.diff(symbol_of(jet, 0, 0)), {{x, 0.5}}) == Approx(3001.0));
  CHECK(nhc::symbols_through(d) == std::set<ex, GiNaC::ex_is_less>{x});
  CHECK(nhc::intermediates_in_order({d}).size() == 3001);
}

TEST_CASE("explicit partials treat intermediates as independent", "[intermediate]") {
  const nhc::JetSpace jet = plane();
  const GiNaC::symbol& sx = symbol_of(jet, 0, 0);
  const ex x = sx;
  const ex d = nhc::Intermediate("d", "d", x * x);
  const ex e = d * x;
  CHECK((e.diff(sx) - (d + 2 * x * x)).expand().is_zero());  // the chain rule
  {
    const nhc::ExplicitDerivatives explicit_only;
    CHECK((e.diff(sx) - d).is_zero());
  }
  CHECK((e.diff(sx) - (d + 2 * x * x)).expand().is_zero());  // the mode ends with its scope
}

TEST_CASE("the total derivative over intermediates equals D of the substituted expression", "[intermediate]") {
  const nhc::JetSpace jet = plane();
  const ex m = jet.parameter(0);
  const ex x = jet.q(0, 0), xd = jet.q(0, 1), y = jet.q(1, 0), yd = jet.q(1, 1);
  const ex v2 = nhc::Intermediate("v2", "v^2", xd * xd + yd * yd);
  const ex T = nhc::Intermediate("T", "T", m * v2 / 2);
  const ex r = nhc::Intermediate("r", "r", sin(x) * y + jet.time());
  const ex e = T * r + v2 * x;
  const nhc::TotalDerivative D([&](const ex& s) -> ex {
    if (s.is_equal(jet.time())) return 1;
    if (const auto c = jet.classify(s)) return jet.symbol({c->kind, c->index, c->order + 1});
    return 0;  // a parameter
  });
  const ex through = nhc::expand_intermediates(D(e));
  const ex plain = jet.total_derivative(nhc::expand_intermediates(e));
  CHECK((through - plain).expand().is_zero());
  // D of an intermediate is computed once: the same object the second time.
  const ex first = GiNaC::ex_to<nhc::Intermediate>(T).total_derivative(D);
  CHECK(GiNaC::ex_to<nhc::Intermediate>(T).total_derivative(D).is_equal(first));
}
