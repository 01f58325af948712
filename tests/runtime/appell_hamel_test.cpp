// Appell–Hamel (chetaev) integrated by the runtime against its closed form (models.md).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "appell_hamel_fixture.hpp"

using namespace nhc::runtime;
using ah_test::AppellHamel;

namespace {

IntegratorOptions tight(LinearSolverKind solver = LinearSolverKind::dense) {
  IntegratorOptions o;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.linear_solver = solver;
  return o;
}

void check_against_closed_form(const AppellHamel& ah, const RunResult& run, double rtol) {
  REQUIRE_FALSE(run.failure.has_value());
  REQUIRE(run.samples.size() > 10);
  double worst = 0;
  for (const Sample& s : run.samples) {
    const std::vector<double> exact = ah.exact(s.t);
    for (int i = 0; i < 7; ++i) {
      const double err = std::abs(s.y[i] - exact[i]) / std::max(1.0, std::abs(exact[i]));
      worst = std::max(worst, err);
      INFO("t = " << s.t << ", state " << i << ": " << s.y[i] << " vs " << exact[i]);
      REQUIRE(err <= 100 * rtol);
    }
  }
  WARN("max relative error against the closed form: " << worst << " (bound " << 100 * rtol << ")");
}

}  // namespace

TEST_CASE("Appell–Hamel chetaev follows the closed form up to 0.9 t*", "[runtime]") {
  const AppellHamel ah;
  const auto times = output_times(0.0, 0.9 * ah.t_star(), 200);
  SECTION("dense LU") {
    const RunResult run = simulate(ah_test::model(), ah.parameters(), ah.initial(), times, tight());
    check_against_closed_form(ah, run, 1e-8);
    CHECK(run.statistics.linear_solver == "dense");
    CHECK(run.statistics.steps > 0);
    CHECK(run.statistics.jacobian_evaluations > 0);
  }
  SECTION("KLU") {
    const RunResult run =
        simulate(ah_test::model(), ah.parameters(), ah.initial(), times, tight(LinearSolverKind::sparse));
    check_against_closed_form(ah, run, 1e-8);
    CHECK(run.statistics.linear_solver == "KLU");
  }
  SECTION("rtol 1e-6") {
    IntegratorOptions o = tight();
    o.rtol = 1e-6;
    o.atol = 1e-8;
    check_against_closed_form(ah, simulate(ah_test::model(), ah.parameters(), ah.initial(), times, o), 1e-6);
  }
}

TEST_CASE("Appell–Hamel chetaev conserves energy to 1e-6 at rtol 1e-8", "[runtime]") {
  const AppellHamel ah;
  const RunResult run =
      simulate(ah_test::model(), ah.parameters(), ah.initial(), output_times(0.0, 0.99 * ah.t_star(), 500), tight());
  REQUIRE_FALSE(run.failure.has_value());
  const DriftReport drift = measure_drift(ah_test::model(), ah.parameters(), run.samples);
  WARN("energy drift " << drift.max_invariant_relative << " relative, hidden-constraint drift " << drift.max_hidden);
  CHECK(drift.max_invariant_relative < 1e-6);
  CHECK(drift.max_hidden < 1e-7);
}

TEST_CASE("Appell–Hamel chetaev stops at t* naming the singular constraint gradient", "[runtime]") {
  const AppellHamel ah;
  const RunResult run =
      simulate(ah_test::model(), ah.parameters(), ah.initial(), output_times(0.0, 2 * ah.t_star(), 100), tight());
  REQUIRE(run.failure.has_value());
  const nhc::base::SolverError& e = *run.failure;
  INFO(e.what());
  CHECK(e.kind() == nhc::base::FailureKind::singular_constraint_gradient);
  CHECK(std::abs(e.t() - ah.t_star()) < 1e-6);
  const std::string message = e.what();
  CHECK(message.find("constraint gradient is singular") != std::string::npos);
  CHECK(message.find("x'^2 + y'^2") != std::string::npos);
  CHECK(message.find("t = 0.28") != std::string::npos);
  // The trajectory holds the solution up to the stop.
  REQUIRE_FALSE(run.samples.empty());
  CHECK(std::abs(run.samples.back().t - e.t()) < 1e-12);
  WARN("stopped at t = " << e.t() << ", exact t* = " << ah.t_star() << ", |diff| = " << std::abs(e.t() - ah.t_star()));
}

TEST_CASE("consistent initialization solves the hidden constraint for what was not given", "[runtime]") {
  const AppellHamel ah;
  Integrator integrator(ah_test::model(), ah.parameters(), tight());
  const Sample s = integrator.initialize(ah.initial(), 0.01);
  const std::vector<double> exact = ah.exact(0.0);
  for (int i = 0; i < 7; ++i) CHECK(s.y[i] == Approx(exact[i]).margin(1e-12));
  // y' from IDACalcIC: x'' = −u_x v', z'' = k v'.
  CHECK(s.yp[5] == Approx(-ah.k() * ah.deceleration()).margin(1e-9));

  SECTION("a given, inconsistent z' is reported, not overwritten") {
    InitialState bad = ah.initial();
    bad.y[5] = 3.0;
    bad.given[5] = true;
    Integrator other(ah_test::model(), ah.parameters(), tight());
    try {
      other.initialize(bad, 0.01);
      FAIL("no exception");
    } catch (const nhc::base::SolverError& e) {
      CHECK(e.kind() == nhc::base::FailureKind::inconsistent_initial_values);
      CHECK(std::string(e.what()).find("f1") != std::string::npos);
      CHECK(e.t() == 0.0);
    }
  }
}

TEST_CASE("events are located and terminal events stop the run", "[runtime]") {
  const AppellHamel ah;
  Event top;
  top.name = "z = 0.05";
  top.function = [](double, const double* y, const double*) { return y[4] - 0.05; };
  top.terminal = true;
  const RunResult run = simulate(ah_test::model(), ah.parameters(), ah.initial(),
                                 output_times(0.0, 0.9 * ah.t_star(), 50), tight(), {top});
  REQUIRE_FALSE(run.failure.has_value());
  REQUIRE(run.events.size() == 1);
  // z = k s(t) = 0.05 with s = v0 t − c t²/2.
  const double c = ah.deceleration(), s = 0.05 / ah.k();
  const double t_exact = (ah.v0() - std::sqrt(ah.v0() * ah.v0() - 2 * c * s)) / c;
  CHECK(run.events[0].t == Approx(t_exact).margin(1e-7));
  CHECK(run.samples.back().t == Approx(t_exact).margin(1e-12));
}
