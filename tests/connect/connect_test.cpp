// nhc::connect against closed-form boundary-value solutions (docs/connect.md).
#include <catch2/catch.hpp>

#include <cmath>

#include "nhc/connect/shooting.hpp"
#include "test_models.hpp"

using namespace nhc;

namespace {

connect::ShootingProblem problem_for(const runtime::Model& model, const std::string& file) {
  const Scene scene = load_scene(std::string(NHC_SOURCE_DIR) + "/examples/" + file);
  connect::ShootingProblem problem{model,
                                   model.default_parameters(),
                                   runtime::initial_state_from(model, scene.initial.t0, scene.initial.values),
                                   {},
                                   {},
                                   1,
                                   1,
                                   runtime::IntegratorOptions{},
                                   1e-10,
                                   50,
                                   20};
  problem.integrator.rtol = 1e-11;
  problem.integrator.atol = 1e-13;
  problem.free_states = connect::default_free_states(model, problem.parameters, problem.initial);
  return problem;
}

connect::Condition condition(const runtime::Model& model, const std::string& name, double value) {
  for (int i = 0; i < model.n_states(); ++i)
    if (model.state_name(i) == name) return {i, name, value};
  FAIL("no state " << name);
  return {};
}

/// φ with (φ − sin φ)/(4 (1 − cos φ)) = ratio, |φ| < 2π (docs/connect.md: z/d² of an arc).
double arc_angle(double ratio) {
  auto h = [](double phi) { return (phi - std::sin(phi)) / (4 * (1 - std::cos(phi))); };
  double lo = 1e-9, hi = 2 * M_PI - 1e-9;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) < ratio ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

TEST_CASE("Heisenberg, vakonomic: from the origin to (x, y, z) on a circular arc", "[connect]") {
  const auto loaded = test::example_model("heisenberg.toml", ModelKind::vakonomic);
  const runtime::Model& model = loaded.model();
  struct Target {
    double x, y, z, T;
    int segments;
  };
  for (const Target target : {Target{1, 0, 0.25, 1, 1}, Target{0.5, 1, 0.1, 2, 1}, Target{1, 0, 0.25, 1, 3}}) {
    connect::ShootingProblem problem = problem_for(model, "heisenberg.toml");
    REQUIRE(problem.free_states.size() == 3);  // x'(0), y'(0), lambda1(0)
    problem.conditions = {condition(model, "x", target.x), condition(model, "y", target.y),
                          condition(model, "z", target.z)};
    problem.t_end = target.T;
    problem.segments = target.segments;
    const connect::ShootingResult found = connect::connect(problem);
    // Closed form: phi = lambda T from z/d^2, speed v = |lambda| d / (2 |sin(phi/2)|), initial
    // direction = the chord's direction − phi/2.
    const double d = std::hypot(target.x, target.y);
    const double phi = arc_angle(target.z / (d * d));
    const double lambda = phi / target.T, v = lambda * d / (2 * std::sin(phi / 2));
    const double direction = std::atan2(target.y, target.x) - phi / 2;
    INFO("segments " << target.segments << ", iterations " << found.history.back().number);
    CHECK(found.miss < 1e-9);
    CHECK(found.values[0] == Approx(v * std::cos(direction)).margin(1e-6));
    CHECK(found.values[1] == Approx(v * std::sin(direction)).margin(1e-6));
    CHECK(found.values[2] == Approx(lambda).margin(1e-6));
    CHECK(found.trajectory.back().t == Approx(target.T));
    CHECK(found.trajectory.back().y[model.state_index(0, 0)] == Approx(target.x).margin(1e-6));
  }
}

TEST_CASE("knife edge (Chaplygin sleigh): speed and turning rate for a target (x, y)", "[connect]") {
  const auto loaded = test::example_model("knife_edge.toml", ModelKind::chetaev);
  const runtime::Model& model = loaded.model();
  connect::ShootingProblem problem = problem_for(model, "knife_edge.toml");
  REQUIRE(problem.free_states.size() == 2);  // x'(0) and phi'(0); y'(0) follows from the constraint
  const double X = 1.0, Y = 0.5, T = 1.0;
  problem.conditions = {condition(model, "x", X), condition(model, "y", Y)};
  problem.t_end = T;
  const connect::ShootingResult found = connect::connect(problem);
  // x = (v/w) sin(w T), y = (v/w)(1 − cos(w T)): w T = 2 atan2(y, x), v = w x / sin(w T).
  const double w = 2 * std::atan2(Y, X) / T, v = w * X / std::sin(w * T);
  CHECK(found.values[0] == Approx(v).margin(1e-6));
  CHECK(found.values[1] == Approx(w).margin(1e-6));
}

TEST_CASE("more free values than conditions: a minimum-norm solution that reaches the target", "[connect]") {
  const auto loaded = test::example_model("heisenberg.toml", ModelKind::vakonomic);
  const runtime::Model& model = loaded.model();
  connect::ShootingProblem problem = problem_for(model, "heisenberg.toml");
  problem.conditions = {condition(model, "x", 1.0), condition(model, "y", 0.5)};
  problem.t_end = 1;
  const connect::ShootingResult found = connect::connect(problem);
  CHECK(found.minimum_norm);
  CHECK(found.miss < 1e-9);
}

TEST_CASE("a free value without influence is named, and an unreachable target reports its best miss", "[connect]") {
  const auto loaded = test::example_model("heisenberg.toml", ModelKind::vakonomic);
  const runtime::Model& model = loaded.model();
  connect::ShootingProblem problem = problem_for(model, "heisenberg.toml");
  problem.t_end = 1;
  problem.conditions = {condition(model, "x", 1.0)};
  problem.free_states = {model.state_index(model.n_coordinates(), 0)};  // lambda1 alone: no velocity
  try {
    connect::connect(problem);
    FAIL("no failure");
  } catch (const connect::ShootingFailure& e) {
    CHECK(e.kind() == connect::ShootingFailure::Kind::singular);
    CHECK(e.uninfluential() == std::vector<std::string>{"lambda1(0)"});
  }
  // With lambda1 = 0 the motion is straight: no area is swept, z = 0.25 cannot be reached.
  problem.free_states = {model.state_index(0, 1), model.state_index(1, 1)};
  problem.conditions = {condition(model, "x", 1.0), condition(model, "y", 0.0), condition(model, "z", 0.25)};
  try {
    connect::connect(problem);
    FAIL("no failure");
  } catch (const connect::ShootingFailure& e) {
    CHECK(e.kind() == connect::ShootingFailure::Kind::no_convergence);
    CHECK(e.history().back().miss == Approx(0.25).margin(1e-6));
  }
}
