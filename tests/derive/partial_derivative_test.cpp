// partial_derivative (nhc/expr/partial_derivative.hpp) against the independent path it replaces,
// GiNaC's own ex::diff: the same expression (is_equal, so the same canonical terms and
// generated code), and the value against central finite differences of a plain C++ evaluation.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "nhc/expr/elementary_derivatives.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/partial_derivative.hpp"

namespace {

using GiNaC::ex;

struct Case {
  std::string what;
  ex expression;                                        ///< over x, y, z
  std::function<double(double, double, double)> value;  ///< the same in C++
};

double at(const ex& e, const GiNaC::exmap& point) {
  const ex v = GiNaC::evalf(nhc::expand_intermediates(e).subs(point));
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

}  // namespace

TEST_CASE("partial_derivative gives GiNaC's derivative, term for term", "[intermediate]") {
  nhc::register_elementary_derivatives();
  const GiNaC::realsymbol x("x"), y("y"), z("z");
  // u := x*y + sin(z), an intermediate: its partials come from its memoized chain rule.
  const ex u = nhc::Intermediate("u", "u", x * y + GiNaC::sin(z));
  const auto u_value = [](double x, double y, double z) { return x * y + std::sin(z); };
  const std::vector<Case> cases = {
      {"a product in which x occurs in one factor of five", 3 * x * y * y * z * GiNaC::cos(y),
       [](double x, double y, double z) { return 3 * x * y * y * z * std::cos(y); }},
      {"a product in which x occurs in every factor", 2 * x * GiNaC::pow(x + y, 3) * GiNaC::sin(x * z),
       [](double x, double y, double z) { return 2 * x * std::pow(x + y, 3) * std::sin(x * z); }},
      {"a sum with a numeric term and nested products", 5 + x * (y + x * z) - GiNaC::pow(y, 2) / (1 + x * x),
       [](double x, double y, double z) { return 5 + x * (y + x * z) - y * y / (1 + x * x); }},
      {"fractional and negative powers", GiNaC::sqrt(x * x + y * y) + GiNaC::pow(x + z, -2),
       [](double x, double y, double z) { return std::sqrt(x * x + y * y) + std::pow(x + z, -2); }},
      {"a symbolic exponent", GiNaC::pow(x + 2, y), [](double x, double y, double) { return std::pow(x + 2, y); }},
      {"functions of sums", GiNaC::atan2(y, x + z) + GiNaC::exp(x * y) * GiNaC::cos(x - z),
       [](double x, double y, double z) { return std::atan2(y, x + z) + std::exp(x * y) * std::cos(x - z); }},
      {"an intermediate in a product and a power", u * x + GiNaC::pow(u, 2) * z,
       [&](double x, double y, double z) { return u_value(x, y, z) * x + std::pow(u_value(x, y, z), 2) * z; }},
      {"an expression without the variables", GiNaC::numeric(7, 3), [](double, double, double) { return 7.0 / 3.0; }},
  };
  const double px = 0.7, py = -1.3, pz = 0.4, h = 1e-6;
  const GiNaC::exmap point{{x, px}, {y, py}, {z, pz}};
  for (const Case& c : cases)
    for (const GiNaC::symbol* s : {&x, &y, &z}) {
      INFO(c.what << ", d/d" << s->get_name() << " of " << c.expression);
      const ex fast = nhc::partial_derivative(c.expression, *s);
      CHECK(fast.is_equal(c.expression.diff(*s)));
      const double dx = s == &x ? h : 0, dy = s == &y ? h : 0, dz = s == &z ? h : 0;
      const double central = (c.value(px + dx, py + dy, pz + dz) - c.value(px - dx, py - dy, pz - dz)) / (2 * h);
      CHECK(at(fast, point) == Approx(central).epsilon(1e-7).margin(1e-8));
    }
}
