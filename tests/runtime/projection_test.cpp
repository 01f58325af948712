// Projection onto the hidden constraints keeps their drift down (docs/projection.md).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "appell_hamel_fixture.hpp"
#include "synthetic_models.hpp"

using namespace nhc::runtime;

namespace {
InitialState pendulum_start() {
  InitialState s;
  s.y = {1.0, 0.0, 0.0, 0.0, 0.0};  // horizontal, at rest
  s.given = {true, true, false, false, false};
  return s;
}
}  // namespace

TEST_CASE("projection reduces the hidden-constraint drift of the index-1 pendulum", "[runtime]") {
  const nhc_model_table table = synthetic::pendulum::table();
  const Model model = Model::from_table(&table);
  IntegratorOptions o;
  o.rtol = 1e-6;
  o.atol = 1e-8;
  const auto times = output_times(0.0, 20.0, 400);
  const RunResult free_run = simulate(model, {}, pendulum_start(), times, o);
  const auto method = GENERATE(ProjectionMethod::in_place, ProjectionMethod::restart);
  o.projection = method;
  const RunResult projected = simulate(model, {}, pendulum_start(), times, o);
  REQUIRE_FALSE(free_run.failure.has_value());
  REQUIRE_FALSE(projected.failure.has_value());
  const DriftReport a = measure_drift(model, model.default_parameters(), free_run.samples);
  const DriftReport b = measure_drift(model, model.default_parameters(), projected.samples);
  WARN((method == ProjectionMethod::in_place ? "in place" : "restart")
       << ": pendulum, t = 20, rtol 1e-6: hidden drift " << a.max_hidden << " -> " << b.max_hidden << ", energy drift "
       << a.max_invariant_relative << " -> " << b.max_invariant_relative << ", steps " << free_run.statistics.steps
       << " -> " << projected.statistics.steps << " (" << projected.statistics.projections << " projections)");
  CHECK(projected.statistics.projections > 0);
  CHECK(b.max_hidden < 0.1 * a.max_hidden);
  CHECK(b.max_hidden < 2e-5);
  if (method == ProjectionMethod::in_place) CHECK(projected.statistics.steps < 1.5 * free_run.statistics.steps);
  CHECK(free_run.statistics.jacobian == "difference quotients");
}

TEST_CASE("Appell–Hamel chetaev does not drift: BDF is exact on its polynomial solution", "[runtime]") {
  const ah_test::AppellHamel ah;
  IntegratorOptions o;
  o.rtol = 1e-4;
  o.atol = 1e-6;
  o.projection = ProjectionMethod::in_place;
  const RunResult run =
      simulate(ah_test::model(), ah.parameters(), ah.initial(), output_times(0.0, 0.9 * ah.t_star(), 50), o);
  REQUIRE_FALSE(run.failure.has_value());
  CHECK(measure_drift(ah_test::model(), ah.parameters(), run.samples).max_hidden < 1e-12);
  CHECK(run.statistics.projections == 0);  // nothing to correct, no restarts
}

namespace {

/// max |g_i(t, y)|, 0 when the model has no hidden constraints.
double hidden_residual(const Model& model, const double* p, double t, const double* y) {
  const int m = model.n_hidden();
  if (m == 0) return 0.0;
  std::vector<double> g(static_cast<std::size_t>(m));
  model.table().hidden_constraints(t, y, p, g.data());
  double worst = 0;
  for (double gi : g) worst = std::isfinite(gi) ? std::max(worst, std::abs(gi)) : INFINITY;
  return worst;
}

}  // namespace

TEST_CASE("the hidden-constraint solve keeps the given values", "[runtime]") {
  const ah_test::AppellHamel ah;
  const Model model = ah_test::model();
  std::vector<double> y = {0, 1.0, 0, 0.5, 0, 0.0, 0};
  const std::vector<double> scale = {0, 0, 0, 0, 0, 1, 0};
  const HiddenSolveReport r = solve_hidden_constraints(model, ah.parameters().data(), 0.0, y.data(), scale, 1e-14);
  CHECK(r.residual_after <= 1e-14);
  CHECK(y[1] == 1.0);
  CHECK(y[3] == 0.5);
  CHECK(y[5] == Approx(ah.k() * ah.v0()).epsilon(1e-14));
  CHECK(hidden_residual(model, ah.parameters().data(), 0.0, y.data()) <= 1e-14);
}
