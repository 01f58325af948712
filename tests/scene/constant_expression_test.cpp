// Numbers as constant expressions in scenes: pi, e, parameters in [initial],
// tolerances and t_end as TOML strings; errors located at the value.
#include <catch2/catch.hpp>

#include <cmath>

#include "nhc/errors.hpp"
#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/scene.hpp"

namespace {

const char* kScene = R"TOML(name = "turntable"
coordinates = ["x", "y"]
lagrangian = "m/2*(x'^2 + y'^2)"

[parameters]
m = 1.0
alpha = "pi/8"
v = "2*e"

[initial]
t0 = "pi/4"
x = [0.0, "v*cos(pi/6)"]
y = ["-alpha", "v*sin(pi/6)"]

[simulate]
t_end = "pi"
rtol = "1e-8"
atol = "10^-10"
outputs = 50
)TOML";

}  // namespace

TEST_CASE("constant expressions evaluate like C++ does", "[scene]") {
  using nhc::evaluate_constant_expression;
  CHECK(evaluate_constant_expression("pi/8") == M_PI / 8);
  CHECK(evaluate_constant_expression("e") == M_E);
  CHECK(evaluate_constant_expression("-2^2") == -4.0);
  CHECK(evaluate_constant_expression("2^3^2") == 512.0);
  CHECK(evaluate_constant_expression("1e-3 * (2 + 3)") == Approx(5e-3).epsilon(1e-15));
  CHECK(evaluate_constant_expression("v*cos(pi/6)", {{"v", 2.0}}) == 2.0 * std::cos(M_PI / 6));
  CHECK(evaluate_constant_expression("sqrt(2)*sqrt(2)") == Approx(2.0).epsilon(1e-15));
  CHECK_THROWS_WITH(evaluate_constant_expression("w + 1"), Catch::Contains("unknown name 'w'"));
  CHECK_THROWS_WITH(evaluate_constant_expression("1/0"), Catch::Contains("division by zero"));
  CHECK_THROWS_WITH(evaluate_constant_expression("sqrt(-1)"), Catch::Contains("not finite"));
  CHECK_THROWS_WITH(evaluate_constant_expression("(1"), Catch::Contains("')' expected"));
  CHECK_THROWS_WITH(evaluate_constant_expression("sin 1"), Catch::Contains("unknown name 'sin'"));
  CHECK_THROWS_WITH(evaluate_constant_expression("foo(1)"), Catch::Contains("unknown function 'foo'"));
}

TEST_CASE("parameters, initial values and [simulate] numbers may be constant expressions", "[scene]") {
  const nhc::Scene s = nhc::parse_scene(kScene, "turntable.toml");
  REQUIRE(s.parameter_values.size() == 3);
  // JetSpace parameter order as listed by the loader: look up by name.
  const auto value = [&](const std::string& name) {
    return s.parameter_values[static_cast<std::size_t>(*s.jet->parameter_index(name))];
  };
  CHECK(value("alpha") == M_PI / 8);
  CHECK(value("v") == 2 * M_E);
  CHECK(s.initial.t0 == M_PI / 4);
  CHECK(s.initial.values.at("x")[1] == 2 * M_E * std::cos(M_PI / 6));
  CHECK(s.initial.values.at("y")[0] == -M_PI / 8);
  CHECK(s.simulate.t_end == M_PI);
  CHECK(s.simulate.rtol == 1e-8);
  CHECK(s.simulate.atol == Approx(1e-10).epsilon(1e-15));
  CHECK(s.simulate.outputs == 50);
}

TEST_CASE("a bad constant expression is located at its value", "[scene]") {
  std::string text = kScene;
  text.replace(text.find("\"v*cos(pi/6)\""), 13, "\"w*cos(pi/6)\"");
  try {
    nhc::parse_scene(text, "turntable.toml");
    FAIL("no error");
  } catch (const nhc::InputError& e) {
    CHECK(e.where().line == 12);
    CHECK(e.where().column == 11);
    CHECK_THAT(e.message(), Catch::Contains("unknown name 'w'"));
  }
}
