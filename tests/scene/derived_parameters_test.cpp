// [parameters] written through other parameters (`Ja = "mw*r^2/2"`): expressions of the parameters
// of the equations, resolved in any order, following every change of the parameters they use.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"

namespace {

// A wheel of mass mw and radius r under a body of mass mb, rolling without slipping.
const char* kWheel = R"TOML(name = "wheel"
coordinates = ["x", "th"]
lagrangian = "m/2*x'^2 + Ja/2*th'^2"
constraints = ["x' - r*th'"]

[parameters]
Ja = "mw*r^2/2"
m = "mw + mb"
Jtotal = "Ja + m*r^2"
mw = 2.0
mb = 1.0
r = 0.5

[initial]
x = [0.0, "r*Jtotal"]
th = [0.0]
lambda1 = [0.0]
)TOML";

double parameter(const nhc::Scene& s, const std::string& name) {
  return s.parameter_values[static_cast<std::size_t>(*s.jet->parameter_index(name))];
}

nhc::InputError refusal(const std::string& text) {
  try {
    nhc::parse_scene(text, "wheel.toml");
  } catch (const nhc::InputError& e) {
    return e;
  }
  FAIL("the scene was accepted");
  throw;
}

}  // namespace

TEST_CASE("parameters computed from parameters are expressions of them, in any order", "[scene][parameters]") {
  const nhc::Scene s = nhc::parse_scene(kWheel, "wheel.toml");
  // Only the numbers are parameters of the equations; the others are expressions of them.
  CHECK(s.jet->parameters().size() == 3);
  CHECK_FALSE(s.jet->parameter_index("Ja"));
  REQUIRE(s.derived_parameters.size() == 3);
  const GiNaC::ex mw = s.jet->parameter(*s.jet->parameter_index("mw"));
  const GiNaC::ex mb = s.jet->parameter(*s.jet->parameter_index("mb"));
  const GiNaC::ex r = s.jet->parameter(*s.jet->parameter_index("r"));
  const GiNaC::ex xd = s.jet->q(0, 1), thd = s.jet->q(1, 1);
  const GiNaC::ex expected = (mw + mb) / 2 * GiNaC::pow(xd, 2) + mw * GiNaC::pow(r, 2) / 4 * GiNaC::pow(thd, 2);
  CHECK((s.lagrangian - expected).expand().is_zero());
  // Jtotal names Ja and m, which are written before and after it: resolved on use.
  const nhc::DerivedParameter* total = s.derived_parameter("Jtotal");
  REQUIRE(total);
  CHECK((total->value - (mw * GiNaC::pow(r, 2) / 2 + (mw + mb) * GiNaC::pow(r, 2))).expand().is_zero());
  // [initial] sees their values: r*Jtotal = 0.5 * (0.25 + 0.75).
  CHECK(s.initial.values.at("x")[1] == Approx(0.5 * (2.0 * 0.25 / 2 + 3.0 * 0.25)).epsilon(1e-15));
  CHECK(s.parameter_values_by_name().at("Ja") == Approx(0.25).epsilon(1e-15));
}

TEST_CASE("[initial] values written through a computed parameter follow its parameters", "[scene][parameters]") {
  nhc::Scene s = nhc::parse_scene(kWheel, "wheel.toml");
  s.parameter_values[static_cast<std::size_t>(*s.jet->parameter_index("mw"))] = 4.0;
  nhc::reevaluate_initial_expressions(s);
  // Jtotal = mw r^2/2 + (mw + mb) r^2 = 0.5 + 1.25 at mw = 4.
  CHECK(s.initial.values.at("x")[1] == Approx(0.5 * 1.75).epsilon(1e-15));
  CHECK(parameter(s, "mw") == 4.0);
}

TEST_CASE("cycles, coordinates and non-numbers among computed parameters are located refusals", "[scene][parameters]") {
  std::string cycle = kWheel;
  cycle.replace(cycle.find("mw = 2.0"), 8, "mw = \"2*Jtotal\"");
  const nhc::InputError c = refusal(cycle);
  CHECK_THAT(c.message(), Catch::Contains("is computed from itself"));
  CHECK(c.where().line >= 7);

  std::string coordinate = kWheel;
  coordinate.replace(coordinate.find("\"mw*r^2/2\""), 10, "\"mw*x^2/2\"");
  const nhc::InputError x = refusal(coordinate);
  CHECK(x.where().line == 7);
  CHECK(x.where().column == 10);
  CHECK_THAT(x.message(), Catch::Contains("coordinate 'x' is not allowed here (only parameters)"));

  std::string time = kWheel;
  time.replace(time.find("\"mw*r^2/2\""), 10, "\"mw*t^2/2\"");
  CHECK_THAT(refusal(time).message(), Catch::Contains("'t' is not allowed here"));

  std::string infinite = kWheel;
  infinite.replace(infinite.find("\"mw*r^2/2\""), 10, "\"mw/(r - 1/2)\"");
  const nhc::InputError inf = refusal(infinite);
  CHECK(inf.where().line == 7);
  CHECK_THAT(inf.message(), Catch::Contains("not a finite number"));
}
