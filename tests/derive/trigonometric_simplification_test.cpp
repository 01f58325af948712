// sin²u + cos²u = 1 where it shortens: the rewritten expression equals the
// original at random points (an independent numeric check) and is shorter.
#include <catch2/catch.hpp>

#include <ginac/ginac.h>

#include <cmath>
#include <random>

#include "nhc/derive/models.hpp"
#include "nhc/expr/simplification.hpp"
#include "nhc/scene/scene.hpp"

using GiNaC::cos;
using GiNaC::ex;
using GiNaC::pow;
using GiNaC::sin;
using nhc::simplify_trigonometric;

namespace {

double at(const ex& e, const GiNaC::exmap& point) {
  return GiNaC::ex_to<GiNaC::numeric>(e.subs(point).evalf()).to_double();
}

}  // namespace

TEST_CASE("sin^2 + cos^2 = 1 shortens expressions and keeps their value", "[derive]") {
  const GiNaC::realsymbol a("a"), l("lambda1"), th("theta"), x("x");
  const ex cases[] = {
      -a * pow(cos(th), 2) * l - a * l * pow(sin(th), 2),                         // the issue's −a λ1
      pow(sin(th), 4) + 2 * pow(sin(th), 2) * pow(cos(th), 2) + pow(cos(th), 4),  // (sin² + cos²)² = 1
      x * pow(sin(2 * th), 2) + x * pow(cos(2 * th), 2) - x,                      // cancels identically
  };
  const ex expected[] = {-a * l, ex(1), ex(0)};
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> u(-2, 2);
  for (std::size_t k = 0; k < 3; ++k) {
    const ex s = simplify_trigonometric(cases[k]);
    INFO(cases[k] << " -> " << s);
    CHECK((s - expected[k]).expand().is_zero());
    for (int trial = 0; trial < 5; ++trial) {
      const GiNaC::exmap p{{a, u(rng)}, {l, u(rng)}, {th, u(rng)}, {x, u(rng)}};
      CHECK(at(s, p) == Approx(at(cases[k], p)).margin(1e-12));
    }
  }
  // No shorter form: unchanged.
  const ex plain = sin(th) * cos(th) + x;
  CHECK(simplify_trigonometric(plain).is_equal(plain));
}

TEST_CASE("derived equations carry no sin^2 + cos^2", "[derive]") {
  const nhc::Scene scene = nhc::parse_scene(R"TOML(name = "slider"
coordinates = ["theta", "r"]
lagrangian = "m/2*(r'^2 + r^2*theta'^2) + m*g*r*cos(theta)"
constraints = ["r' - a*cos(theta)^2*theta' - a*sin(theta)^2*theta'"]
[parameters]
m = 1.0
g = 9.81
a = 0.5
)TOML",
                                            "slider.toml");
  const nhc::DerivedModel model = nhc::derive_model(scene, nhc::ModelKind::chetaev);
  REQUIRE(model.equations.size() == 2);
  const ex r_theta = model.equations[0];
  INFO(r_theta);
  // R_theta = −∂L/∂θ + d/dt ∂L/∂θ' ... with the multiplier term λ1 ∂f/∂θ' = −a λ1 (sin² + cos²).
  CHECK_FALSE(r_theta.has(pow(sin(GiNaC::wild()), 2)));
  CHECK_FALSE(r_theta.has(pow(cos(GiNaC::wild()), 2)));
}
