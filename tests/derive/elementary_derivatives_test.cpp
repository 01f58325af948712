// Explicit derivatives of the elementary functions (nhc/expr/elementary_derivatives.hpp), checked
// against central finite differences of std:: functions — the independent path — for each function
// the scene language offers, composed with an inner function so that the chain rule is exercised.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "nhc/expr/elementary_derivatives.hpp"

namespace {

using GiNaC::ex;

struct Case {
  std::string name;
  std::function<ex(const ex&)> symbolic;
  std::function<double(double u, double x)> numeric;  ///< the same with std:: functions
  double at;                                          ///< a point inside the function's domain for the inner argument
};

double value_at(const ex& e, const GiNaC::symbol& x, double at) {
  const ex v = GiNaC::evalf(e.subs(x == at));
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

}  // namespace

TEST_CASE("the registered derivatives of the elementary functions match finite differences", "[intermediate]") {
  nhc::register_elementary_derivatives();
  nhc::register_elementary_derivatives();  // idempotent
  const GiNaC::symbol x("x");
  // The inner function u(x) = x/3 + x^2/10 keeps every argument inside the domains below.
  const auto inner = [](const ex& a) { return a / 3 + GiNaC::pow(a, 2) / 10; };
  const auto inner_value = [](double a) { return a / 3 + a * a / 10; };
  const std::vector<Case> cases = {
      {"sin", [](const ex& a) { return GiNaC::sin(a); }, [](double u, double) { return std::sin(u); }, 0.7},
      {"cos", [](const ex& a) { return GiNaC::cos(a); }, [](double u, double) { return std::cos(u); }, 0.7},
      {"tan", [](const ex& a) { return GiNaC::tan(a); }, [](double u, double) { return std::tan(u); }, 0.7},
      {"exp", [](const ex& a) { return GiNaC::exp(a); }, [](double u, double) { return std::exp(u); }, 0.7},
      {"log", [](const ex& a) { return GiNaC::log(a); }, [](double u, double) { return std::log(u); }, 0.7},
      {"sinh", [](const ex& a) { return GiNaC::sinh(a); }, [](double u, double) { return std::sinh(u); }, 0.7},
      {"cosh", [](const ex& a) { return GiNaC::cosh(a); }, [](double u, double) { return std::cosh(u); }, 0.7},
      {"tanh", [](const ex& a) { return GiNaC::tanh(a); }, [](double u, double) { return std::tanh(u); }, 0.7},
      {"asin", [](const ex& a) { return GiNaC::asin(a); }, [](double u, double) { return std::asin(u); }, 0.7},
      {"acos", [](const ex& a) { return GiNaC::acos(a); }, [](double u, double) { return std::acos(u); }, 0.7},
      {"atan", [](const ex& a) { return GiNaC::atan(a); }, [](double u, double) { return std::atan(u); }, 0.7},
      {"asinh", [](const ex& a) { return GiNaC::asinh(a); }, [](double u, double) { return std::asinh(u); }, 0.7},
      {"acosh", [](const ex& a) { return GiNaC::acosh(a); }, [](double u, double) { return std::acosh(u); }, 3.5},
      {"atanh", [](const ex& a) { return GiNaC::atanh(a); }, [](double u, double) { return std::atanh(u); }, 0.7},
      {"atan2(u, 1 + x)", [&](const ex& a) { return GiNaC::atan2(a, 1 + x); },
       [](double u, double a) { return std::atan2(u, 1 + a); }, 0.7},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const ex f = c.symbolic(inner(x));
    const double derivative = value_at(f.diff(x), x, c.at);
    const auto g = [&](double a) { return c.numeric(inner_value(a), a); };
    const double h = 1e-5;
    const double central = (g(c.at + h) - g(c.at - h)) / (2 * h);
    CHECK(derivative == Approx(central).epsilon(1e-8));
    // Second derivatives go through the registered derivative of the derivative's functions.
    const double second = value_at(f.diff(x, 2), x, c.at);
    const double central2 = (g(c.at + h) - 2 * g(c.at) + g(c.at - h)) / (h * h);
    CHECK(second == Approx(central2).epsilon(1e-4));
  }
}

TEST_CASE("an argument free of the symbol gives a zero derivative", "[intermediate]") {
  nhc::register_elementary_derivatives();
  const GiNaC::symbol x("x"), y("y");
  CHECK(GiNaC::sin(y).diff(x).is_zero());
  CHECK(GiNaC::atan2(y, 2 * y).diff(x).is_zero());
  CHECK((GiNaC::cos(x) * GiNaC::exp(y)).diff(y).is_equal(GiNaC::cos(x) * GiNaC::exp(y)));
}
