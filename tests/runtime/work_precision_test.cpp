// The library's work-precision measurement (nhc/runtime/work_precision.hpp) on the hand-written
// Appell–Hamel model, its errors checked against the closed form (appell_hamel_fixture.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "appell_hamel_fixture.hpp"

using namespace nhc::runtime;
using ah_test::AppellHamel;

TEST_CASE("work-precision returns one measurement per configuration and tolerance", "[runtime]") {
  const AppellHamel ah;
  const Model model = ah_test::model();
  WorkPrecisionSettings settings;
  settings.rtols = {1e-4, 1e-6, 1e-8};
  settings.t_end = 0.2;  // before t* = 0.285
  settings.outputs = 20;
  settings.max_repeats = 1;
  settings.configurations = {{"dense", false}, {"sparse", true}};
  WorkPrecisionModels models;
  models.dense = &model;
  models.sparse = &model;  // the hand-written header carries both Jacobians
  const std::map<std::string, std::vector<double>> initial{
      {"x", {ah.x0, ah.vx0}}, {"y", {ah.y0, ah.vy0}}, {"z", {ah.z0}}, {"lambda1", {0.0}}};
  const WorkPrecision wp = measure_work_precision(models, 0.0, initial, settings);

  CHECK(wp.scene_name == model.scene_name());
  CHECK(wp.n_states == model.n_states());
  REQUIRE(wp.measurements.size() == 6);
  CHECK(wp.measurements[0].configuration.label() == "dense");
  CHECK(wp.measurements[3].configuration.label() == "sparse + projection");

  // The true error of a run at the same settings, against the closed form: the measured error
  // (against the reference run, or the model's reference solution) is of its size.
  const std::vector<double> times = output_times(0.0, settings.t_end, settings.outputs);
  for (const WorkPrecisionMeasurement& m : wp.measurements) {
    INFO(m.configuration.label() << " rtol " << m.rtol);
    CHECK(m.status() == "ok");
    CHECK(m.t_reached == Approx(settings.t_end));
    IntegratorOptions o;
    o.rtol = m.rtol;
    o.atol = m.atol;
    o.linear_solver = m.configuration.jacobian == "sparse" ? LinearSolverKind::sparse : LinearSolverKind::dense;
    o.projection = m.configuration.projection ? ProjectionMethod::in_place : ProjectionMethod::none;
    const RunResult run = simulate(model, ah.parameters(), ah.initial(), times, o);
    double true_error = 0;
    for (const Sample& s : run.samples) {
      const std::vector<double> exact = ah.exact(s.t);
      for (int i : {0, 2, 4}) true_error = std::max(true_error, std::abs(s.y[i] - exact[i]));
    }
    CHECK(std::abs(m.error - true_error) <= 1e-3 * true_error + 1e-11);
  }
  // Tighter tolerances give smaller errors.
  CHECK(wp.measurements[2].error < 1e-2 * wp.measurements[0].error);
}
