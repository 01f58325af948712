// Consistent initial values: solved from the hidden constraints, violations named, repair by
// the nearest consistent point, notes for values a model does not need; and the leading
// derivatives at t0 against the closed-form Chetaev motion of Appell–Hamel (models.md).
#include <catch2/catch.hpp>

#include <cmath>

#include "analysis_test_support.hpp"
#include "nhc/analysis/consistent_initialization.hpp"
#include "nhc/errors.hpp"

using namespace nhc;
using Catch::Matchers::Contains;

namespace {

double value(const ConsistentPoint& p, const std::string& name) {
  for (const auto* list : {&p.values, &p.leading})
    for (const auto& v : *list)
      if (v.name == name) return v.value;
  throw std::runtime_error("no value " + name);
}

}  // namespace

TEST_CASE("chetaev Appell-Hamel: z' from f1, lambda and accelerations in closed form", "[sigma]") {
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  const ConsistentPoint p = consistent_initial_point(s, test::structure_of(s, ModelKind::chetaev));
  const double m = 1.0, g = 9.81, k = 0.5, vx = 1.0, vy = 0.5, v = std::hypot(vx, vy);
  CHECK(value(p, "z'") == Approx(k * v));  // f1 = z' − k v = 0
  // λ = m g/(1 + k²), v' = −g k/(1 + k²) along the fixed horizontal direction, z'' = k v'.
  CHECK(value(p, "lambda1") == Approx(m * g / (1 + k * k)));
  const double vdot = -g * k / (1 + k * k);
  CHECK(value(p, "x''") == Approx(vdot * vx / v));
  CHECK(value(p, "y''") == Approx(vdot * vy / v));
  CHECK(value(p, "z''") == Approx(k * vdot));
  REQUIRE(p.constraint_residuals.size() == 1);
  CHECK(std::abs(p.constraint_residuals[0]) < 1e-12);
  // λ is given in the scene but d_λ = 0: a note says it is only a starting guess.
  bool noted = false;
  for (const auto& n : p.notes)
    noted = noted || (n.find("lambda1") != std::string::npos && n.find("starting guess") != std::string::npos);
  CHECK(noted);
}

TEST_CASE("a given value violating a hidden constraint is an error, or repaired", "[sigma]") {
  // z'(0) = 0 with x' = 1, y' = 0: f1 = z' − k|x'| = −0.5.
  const Scene s = test::scene_at("tests/analysis/scenes/appell_hamel_inconsistent.toml");
  const StructuralAnalysis a = test::structure_of(s, ModelKind::chetaev);
  CHECK_THROWS_WITH(consistent_initial_point(s, a),
                    Contains("hidden constraint f1") && Contains("residual -0.5") && Contains("repaired"));
  CHECK_THROWS_AS(consistent_initial_point(s, a), InconsistentInitialValues);
  InitializationOptions repair;
  repair.repair = true;
  const ConsistentPoint p = consistent_initial_point(s, a, repair);
  // Nearest point of the line z' = k x' (x' > 0) to (x', z') = (1, 0): x' = 1/(1 + k²) = 0.8,
  // z' = k/(1 + k²) = 0.4; the other given values stay.
  CHECK(value(p, "x'") == Approx(0.8));
  CHECK(value(p, "z'") == Approx(0.4));
  CHECK(value(p, "y'") == 0.0);
  CHECK(value(p, "x") == 0.0);
}

TEST_CASE("vakonomic particle: a needed value that is not given is defaulted with a note", "[sigma]") {
  const Scene s = test::scene_at("examples/particle.toml");
  const ConsistentPoint p = consistent_initial_point(s, test::structure_of(s, ModelKind::vakonomic));
  CHECK(value(p, "lambda1'") == 0.0);
  bool noted = false;
  for (const auto& n : p.notes) noted = noted || n.find("lambda1'") != std::string::npos;
  CHECK(noted);
  // R_i = (λ' − 1) q_i'' + λ'' q_i' with λ' = 0 and f = q'·q'' = 0: q'' = λ'' q' and
  // |q'|² λ'' = 0, so q'' = 0 and λ'' = 0.
  for (const char* name : {"q1''", "q2''", "q3''", "lambda1''"}) CHECK(std::abs(value(p, name)) < 1e-12);
}

TEST_CASE("suslov Appell-Hamel starts on its monitored constraint", "[sigma]") {
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  const ConsistentPoint p = consistent_initial_point(s, test::structure_of(s, ModelKind::suslov));
  CHECK(value(p, "z'") == Approx(0.5 * std::hypot(1.0, 0.5)));
}
