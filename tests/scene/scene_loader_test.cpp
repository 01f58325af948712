// Scene loader: the issue's example scene, defaults, and errors located at FILE:LINE:COLUMN.
// (The malformed-input corpus under tests/bad/ is run through the real binary in tests/cli.)
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <string>

#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"

using GiNaC::ex;

namespace {

const char* kIssueScene = R"toml(name = "appell_hamel"            # becomes a C++ identifier and a file name
coordinates = ["x", "y", "z"]
lagrangian = "m/2*(x'^2 + y'^2 + z'^2) - m*g*z"
constraints = ["z' - b/a*sqrt(x'^2 + y'^2)"]
dependent = ["z"]                # dependent coordinates, for the suslov model; optional
models = ["vakonomic", "chetaev", "holder", "suslov"]   # optional; default: all

[parameters]
m = 1.0
g = 9.81
a = 1.0
b = 0.5

[initial]                        # t0, and per coordinate or multiplier [value, 1st derivative, ...]
t0 = 0.0
x = [0.0, 1.0]
y = [0.0, 0.5]
z = [0.0]
lambda1 = [0.0]

[simulate]
model = "chetaev"
t_end = 2.0
rtol = 1e-8
atol = 1e-10

[reference]                      # optional exact solution, expressions in t
x = "t"

[invariants]                     # optional named quantities that should stay constant
energy = "m/2*(x'^2 + y'^2 + z'^2) + m*g*z"
)toml";

bool same(const ex& a, const ex& b) { return (a - b).expand().normal().is_zero(); }

nhc::SourceLocation error_at(const std::string& text) {
  try {
    nhc::parse_scene(text, "s.toml");
  } catch (const nhc::InputError& e) {
    return e.where();
  }
  return {"", -1, -1};
}

}  // namespace

TEST_CASE("the issue's example scene loads", "[scene][loader]") {
  const nhc::Scene s = nhc::parse_scene(kIssueScene, "appell_hamel.toml");
  CHECK(s.name == "appell_hamel");
  REQUIRE(s.coordinate_count() == 3);
  CHECK(s.jet->coordinates() == std::vector<std::string>{"x", "y", "z"});
  REQUIRE(s.constraint_count() == 1);
  CHECK(s.jet->multiplier_count() == 1);
  REQUIRE(s.dependent == std::vector<int>{2});
  CHECK(s.models.size() == 4);

  const auto& jet = *s.jet;
  const ex m = jet.parameter(*jet.parameter_index("m"));
  const ex g = jet.parameter(*jet.parameter_index("g"));
  const ex a = jet.parameter(*jet.parameter_index("a"));
  const ex b = jet.parameter(*jet.parameter_index("b"));
  const ex xd = jet.q(0, 1), yd = jet.q(1, 1), zd = jet.q(2, 1), z = jet.q(2, 0);
  CHECK(same(s.lagrangian, m / 2 * (xd * xd + yd * yd + zd * zd) - m * g * z));
  CHECK(same(s.constraints[0], zd - b / a * GiNaC::sqrt(xd * xd + yd * yd)));

  // Parameter values reach the substitution map.
  const GiNaC::exmap values = s.parameter_substitution();
  CHECK(GiNaC::ex_to<GiNaC::numeric>(g.subs(values)).to_double() == Approx(9.81));
  CHECK(GiNaC::ex_to<GiNaC::numeric>(b.subs(values)).to_double() == Approx(0.5));

  CHECK(s.initial.t0 == 0.0);
  CHECK(s.initial.values.at("x") == std::vector<double>{0.0, 1.0});
  CHECK(s.initial.values.at("lambda1") == std::vector<double>{0.0});
  REQUIRE(s.simulate.model.has_value());
  CHECK(*s.simulate.model == nhc::ModelKind::chetaev);
  CHECK(s.simulate.t_end == 2.0);
  CHECK(s.simulate.rtol == 1e-8);
  CHECK(s.simulate.atol == 1e-10);
  REQUIRE(s.reference.all.size() == 1);
  CHECK(s.reference.per_model.empty());
  CHECK(s.reference.all[0].first == 0);
  CHECK(same(s.reference.all[0].second, jet.time()));
  REQUIRE(s.invariants.size() == 1);
  CHECK(s.invariants[0].name == "energy");
  CHECK(!s.invariants[0].required);
  CHECK(same(s.invariants[0].expression, m / 2 * (xd * xd + yd * yd + zd * zd) + m * g * z));
}

TEST_CASE("optional keys take their defaults", "[scene][loader]") {
  const nhc::Scene s =
      nhc::parse_scene("name = \"free\"\ncoordinates = [\"q\"]\nlagrangian = \"q'^2/2\"\n", "free.toml");
  CHECK(s.constraint_count() == 0);
  CHECK(s.dependent.empty());
  CHECK(s.models.size() == 4);
  CHECK(!s.simulate.model.has_value());
  CHECK(s.reference.empty());
  CHECK(s.invariants.empty());
}

TEST_CASE("the examples load", "[scene][loader]") {
  for (const char* name : {"particle", "appell_hamel"}) {
    INFO(name);
    const nhc::Scene s = nhc::load_scene(std::string(NHC_SOURCE_DIR) + "/examples/" + name + ".toml");
    CHECK(s.name == name);
    CHECK(s.constraint_count() == 1);
  }
}

TEST_CASE("scene errors point at the offending text", "[scene][loader]") {
  const std::string head = "name = \"s\"\ncoordinates = [\"x\", \"y\"]\n";
  SECTION("expression error: column of the character inside the string") {
    const auto loc = error_at(head + "lagrangian = \"x'^2 + * y\"\n");
    CHECK(loc.file == "s.toml");
    CHECK(loc.line == 3);
    CHECK(loc.column == 22);
  }
  SECTION("literal strings map columns too") {
    const auto loc = error_at(head + "lagrangian = 'x + foo'\n");
    CHECK(loc.line == 3);
    CHECK(loc.column == 19);
  }
  SECTION("unknown key") {
    const auto loc = error_at(head + "lagrangian = \"x'^2\"\nlagrangain = 1\n");
    CHECK(loc.line == 4);
    CHECK(loc.column == 1);
  }
  SECTION("missing key") {
    const auto loc = error_at(head);
    CHECK(loc.line >= 1);
    CHECK(loc.column >= 1);
  }
  SECTION("name used twice across coordinates and parameters") {
    const auto loc = error_at(head + "lagrangian = \"x'^2\"\n[parameters]\ny = 2\n");
    CHECK(loc.line == 5);
    CHECK(loc.column == 1);
  }
  SECTION("identically zero constraint") {
    const auto loc = error_at(head + "lagrangian = \"x'^2\"\nconstraints = [\"x'*y - y*x' + 0\"]\n");
    CHECK(loc.line == 4);
    CHECK(loc.column == 16);
  }
  SECTION("a constraint that vanishes only after simplification") {
    const auto loc = error_at(head + "lagrangian = \"x'^2\"\nconstraints = [\"sin(x)^2 + cos(x)^2 - 1\"]\n");
    CHECK(loc.line == 4);
  }
}

TEST_CASE("reserved names are refused", "[scene][loader]") {
  for (const char* bad : {"t", "lambda1", "sin", "x_d1", "class", "Pi", "2x", "a-b"}) {
    INFO(bad);
    const auto loc = error_at(std::string("name = \"s\"\ncoordinates = [\"") + bad + "\"]\nlagrangian = \"1\"\n");
    CHECK(loc.line == 2);
    CHECK(loc.column == 16);
  }
  CHECK(nhc::is_valid_identifier("_x1"));
  CHECK(!nhc::is_valid_identifier("namespace"));
  CHECK(!nhc::is_valid_identifier(""));
  CHECK(!nhc::is_valid_identifier("x\xc3\xa9"));
}

TEST_CASE("references per model, invariants with multipliers, required entries", "[scene][loader]") {
  const std::string head =
      "name = \"s\"\ncoordinates = [\"x\", \"y\"]\nlagrangian = \"x'^2 + y'^2\"\nconstraints = [\"x' - y\"]\n";
  const nhc::Scene s =
      nhc::parse_scene(head +
                           "[reference]\nx = \"t\"\ny = \"1\"\n"
                           "[reference.vakonomic]\ny = \"2\"\n"
                           "[invariants]\nb = \"lambda1\"\na = { expression = \"x\", required = true }\n",
                       "s.toml");
  const ex t = s.jet->time();
  REQUIRE(s.reference.all.size() == 2);
  REQUIRE(s.reference.per_model.size() == 1);
  const nhc::SceneReference::Entries chetaev = s.reference.for_model(nhc::ModelKind::chetaev);
  const nhc::SceneReference::Entries vakonomic = s.reference.for_model(nhc::ModelKind::vakonomic);
  REQUIRE(chetaev.size() == 2);
  REQUIRE(vakonomic.size() == 2);
  CHECK(same(chetaev[0].second, t));
  CHECK(same(chetaev[1].second, 1));
  CHECK(vakonomic[0].first == 0);
  CHECK(same(vakonomic[0].second, t));  // the plain table's, for the coordinate the model's omits
  CHECK(vakonomic[1].first == 1);
  CHECK(same(vakonomic[1].second, 2));
  // File order, not the table's alphabetical order.
  REQUIRE(s.invariants.size() == 2);
  CHECK(s.invariants[0].name == "b");
  CHECK(same(s.invariants[0].expression, s.jet->lambda(0, 0)));
  CHECK(!s.invariants[0].required);
  CHECK(s.invariants[1].name == "a");
  CHECK(s.invariants[1].required);
  CHECK(s.invariants[1].where.line == 12);
  CHECK(s.invariants[1].where.column == 20);

  // Located refusals.
  CHECK(error_at(head + "[reference.sideways]\nx = \"t\"\n").line == 5);
  CHECK(error_at(head + "[reference.chetaev]\nz = \"t\"\n").line == 6);
  CHECK(error_at(head + "[reference.chetaev.more]\nx = \"t\"\n").line == 5);
  CHECK(error_at(head + "[invariants]\na = { expression = \"x\", required = 1 }\n").column == 36);
  CHECK(error_at(head + "[invariants]\na = { expresion = \"x\" }\n").line == 6);
  CHECK(error_at(head + "[outputs]\na = { required = true }\n").line == 6);
}
