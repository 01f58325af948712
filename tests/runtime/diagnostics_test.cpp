// Failures end with a SolverError that says what failed and at which t (goal: never a crash,
// hang or silent NaN).
#include <catch2/catch.hpp>

#include <idas/idas.h>

#include <string>

#include "appell_hamel_fixture.hpp"
#include "nhc/runtime/sundials.hpp"
#include "synthetic_models.hpp"

using namespace nhc::runtime;

namespace {

IntegratorOptions quiet() {
  IntegratorOptions o;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  return o;
}

InitialState start() {
  InitialState s;
  s.y = {0.0, 1.0};
  s.given = {true, false};
  return s;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("SUNDIALS return codes become SolverErrors in words, with t", "[runtime]") {
  CHECK_NOTHROW(sun::check(IDA_SUCCESS, "a step", 1.0));
  CHECK_NOTHROW(sun::check(IDA_ROOT_RETURN, "a step", 1.0));
  try {
    sun::check(IDA_CONV_FAIL, "the integration step", 1.5, "at t = 1.5, mxstep steps taken");
    FAIL("no exception");
  } catch (const nhc::base::SolverError& e) {
    const std::string m = e.what();
    CHECK(contains(m, "the integration step failed at t = 1.5"));
    CHECK(contains(m, "failed to converge"));
    CHECK(contains(m, "mxstep"));
    CHECK(e.kind() == nhc::base::FailureKind::convergence);
    CHECK(e.t() == 1.5);
  }
  CHECK(sun::classify_ida_flag(IDA_TOO_MUCH_WORK) == nhc::base::FailureKind::too_many_steps);
  CHECK(sun::classify_ida_flag(IDA_ERR_FAIL) == nhc::base::FailureKind::error_test);
  CHECK(sun::classify_ida_flag(IDA_LSETUP_FAIL) == nhc::base::FailureKind::singular_iteration_matrix);
  CHECK(sun::classify_ida_flag(IDA_REP_RES_ERR) == nhc::base::FailureKind::nonfinite_residual);
  CHECK(contains(sun::describe_ida_flag(-12345), "-12345"));
  CHECK(std::string(to_string(nhc::base::FailureKind::singular_constraint_gradient)) == "singular constraint gradient");
}

TEST_CASE("NaN in a residual is reported with its name and t", "[runtime]") {
  const nhc_model_table table = synthetic::table(&synthetic::nan_residual, &synthetic::nan_jacobian);
  const Model model = Model::from_table(&table);
  const RunResult run = simulate(model, {}, start(), output_times(0.0, 1.0, 10), quiet());
  REQUIRE(run.failure.has_value());
  INFO(run.failure->what());
  CHECK(run.failure->kind() == nhc::base::FailureKind::nonfinite_residual);
  CHECK(run.failure->t() >= 0.5);
  CHECK(run.failure->t() < 0.6);
  CHECK(contains(run.failure->what(), "breakdown"));
  CHECK(contains(run.failure->what(), "NaN"));
  // Solution kept up to the failure.
  REQUIRE_FALSE(run.samples.empty());
  CHECK(run.samples.back().t <= 0.5);
  CHECK(run.samples.back().t > 0.45);
}

TEST_CASE("a singular iteration matrix is reported with t", "[runtime]") {
  const nhc_model_table table = synthetic::table(&synthetic::singular_residual, &synthetic::singular_jacobian);
  const Model model = Model::from_table(&table);
  const RunResult run = simulate(model, {}, start(), output_times(0.0, 1.0, 10), quiet());
  REQUIRE(run.failure.has_value());
  INFO(run.failure->what());
  CHECK(run.failure->kind() == nhc::base::FailureKind::singular_iteration_matrix);
  CHECK(run.failure->t() == Approx(0.5).margin(0.01));
  CHECK(contains(run.failure->what(), "iteration matrix"));
  CHECK(contains(run.failure->what(), "w"));
}

TEST_CASE("the step limit is reported with t", "[runtime]") {
  const ah_test::AppellHamel ah;
  IntegratorOptions o = quiet();
  o.max_steps = 20;
  const RunResult run = simulate(ah_test::model(), ah.parameters(), ah.initial(), {0.0, 0.2}, o);
  REQUIRE(run.failure.has_value());
  CHECK(run.failure->kind() == nhc::base::FailureKind::too_many_steps);
  CHECK(run.failure->t() > 0.0);
  CHECK(run.failure->t() < 0.2);
  CHECK(contains(run.failure->what(), "step limit (20 steps)"));
  CHECK(run.statistics.steps == 20);
}

TEST_CASE("starting on the singular set is refused at t0", "[runtime]") {
  const ah_test::AppellHamel ah;
  InitialState s = ah.initial();
  s.y[1] = s.y[3] = 0.0;  // v = 0: x'/v undefined
  const RunResult run = simulate(ah_test::model(), ah.parameters(), s, {0.0, 0.1}, quiet());
  REQUIRE(run.failure.has_value());
  INFO(run.failure->what());
  CHECK(run.failure->kind() == nhc::base::FailureKind::singular_constraint_gradient);
  CHECK(run.failure->t() == 0.0);
}
