// [inputs]: a scene's inputs through generated code and nhc::runtime, against closed
// forms of the driven oscillator x'' = -x + u (unit mass and stiffness, [forces] x = "u"):
// - the default signal u = sin(2t) from rest: x = (2 sin t - sin 2t)/3;
// - a feedback law u(t, y) = -2 x' (set_inputs): critical damping, x = (x0 + (v0 + x0) t) e^-t;
// - sampled-data control, u held constant on [t_k, t_k+1) (hold_inputs): on each interval
//   x = u_k + (x_k - u_k) cos(t - t_k) + v_k sin(t - t_k), v = -(x_k - u_k) sin(t - t_k) + v_k cos(t - t_k).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace fs = std::filesystem;

namespace {

nhc::Scene oscillator(double x0, double v0) {
  const std::string text =
      "name = \"driven_oscillator\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - x^2/2\"\n"
      "[inputs]\nu = \"sin(2*t)\"\n[forces]\nx = \"u\"\n[initial]\nx = [" +
      std::to_string(x0) + ", " + std::to_string(v0) + "]\n";
  return nhc::parse_scene(text, "driven_oscillator.toml");
}

nhc::jit::LoadedModel build(const nhc::Scene& scene) {
  nhc::jit::BuildOptions options;
  options.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "inputs-cache";
  return nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
}

nhc::runtime::IntegratorOptions tight() {
  nhc::runtime::IntegratorOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  return options;
}

}  // namespace

TEST_CASE("inputs: the model table names the inputs, the default signal drives the motion", "[jit][inputs]") {
  const nhc::Scene scene = oscillator(0.0, 0.0);
  const nhc::jit::LoadedModel built = build(scene);
  const nhc::runtime::Model& model = built.model();
  REQUIRE(model.n_inputs() == 1);
  CHECK(model.input_name(0) == "u");
  CHECK(model.input_index("u") == 0);
  CHECK(model.input_index("v") == -1);
  const nhc::runtime::RunResult run =
      nhc::runtime::simulate(model, {}, nhc::runtime::initial_state_from(model, 0.0, scene.initial.values),
                             nhc::runtime::output_times(0.0, 3.0, 60), tight());
  REQUIRE_FALSE(run.failure);
  double worst = 0;
  for (const nhc::runtime::Sample& s : run.samples) {
    worst = std::max(worst, std::abs(s.y[0] - (2 * std::sin(s.t) - std::sin(2 * s.t)) / 3));
    REQUIRE(s.u.size() == 1);
    CHECK(s.u[0] == Approx(std::sin(2 * s.t)).margin(1e-15));
  }
  CHECK(worst < 1e-8);
}

TEST_CASE("inputs: a feedback law u(t, y) is evaluated at every residual call", "[jit][inputs]") {
  const double x0 = 1.0, v0 = 0.5;
  const nhc::Scene scene = oscillator(x0, v0);
  const nhc::jit::LoadedModel built = build(scene);
  const nhc::runtime::Model& model = built.model();
  const int velocity = model.state_index(0, 1);
  REQUIRE(velocity >= 0);
  nhc::runtime::Integrator integrator(model, {}, tight());
  integrator.set_inputs([velocity](double, const double* y, double* u) { u[0] = -2 * y[velocity]; });
  integrator.initialize(nhc::runtime::initial_state_from(model, 0.0, scene.initial.values), 0.1);
  double worst = 0;
  integrator.integrate(nhc::runtime::output_times(0.0, 5.0, 50), [&](const nhc::runtime::Sample& s) {
    worst = std::max(worst, std::abs(s.y[0] - (x0 + (v0 + x0) * s.t) * std::exp(-s.t)));
  });
  CHECK(worst < 1e-8);
}

TEST_CASE("inputs: values held between sampling times (sampled-data control)", "[jit][inputs]") {
  const double x0 = 1.0, v0 = 0.0, period = 0.25, gain = 0.8;
  const nhc::Scene scene = oscillator(x0, v0);
  const nhc::jit::LoadedModel built = build(scene);
  const nhc::runtime::Model& model = built.model();
  const int position = model.state_index(0, 0), velocity = model.state_index(0, 1);
  nhc::runtime::Integrator integrator(model, {}, tight());
  integrator.hold_inputs({-gain * x0});  // before initialize: the inputs it starts with
  nhc::runtime::Sample now =
      integrator.initialize(nhc::runtime::initial_state_from(model, 0.0, scene.initial.values), period);
  double x = x0, v = v0, worst = 0;  // the closed form, interval by interval
  for (int k = 0; k < 20; ++k) {
    const double t_k = k * period, u = -gain * now.y[static_cast<std::size_t>(position)];  // the controller samples x
    integrator.hold_inputs({u});
    // The closed form from the exact state at t_k (its own, not the integrator's).
    const double u_exact = -gain * x;
    integrator.integrate({t_k + period}, [&](const nhc::runtime::Sample& s) { now = s; });
    const double c = std::cos(period), sn = std::sin(period);
    const double x_next = u_exact + (x - u_exact) * c + v * sn, v_next = -(x - u_exact) * sn + v * c;
    x = x_next;
    v = v_next;
    worst = std::max({worst, std::abs(now.y[static_cast<std::size_t>(position)] - x),
                      std::abs(now.y[static_cast<std::size_t>(velocity)] - v)});
    CHECK(now.u[0] == u);
  }
  CHECK(worst < 1e-8);
}

TEST_CASE("inputs: forward sensitivities follow the default signal", "[jit][inputs]") {
  // x'' = -x + sin 2t from rest: x = (2 sin t - sin 2t)/3 and dx/dx(0) = cos t (the input does
  // not depend on x(0)); every sample carries u = sin 2t.
  const nhc::Scene scene = oscillator(0.0, 0.0);
  nhc::jit::BuildOptions options;
  options.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "inputs-cache";
  options.sensitivities = true;
  const nhc::jit::LoadedModel built = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
  const nhc::runtime::Model& model = built.model();
  nhc::runtime::SensitivityParameter x0;
  x0.kind = nhc::runtime::SensitivityParameter::Kind::initial_value;
  x0.index = model.state_index(0, 0);
  x0.name = "x(0)";
  const nhc::runtime::InitialState initial = nhc::runtime::initial_state_from(model, 0.0, scene.initial.values);
  std::vector<double> times;
  for (int k = 0; k <= 30; ++k) times.push_back(0.1 * k);
  const nhc::runtime::SensitivityRun run =
      nhc::runtime::simulate_sensitivities(model, model.default_parameters(), initial, {x0}, times, tight());
  REQUIRE(!run.failure);
  REQUIRE(run.samples.size() == times.size());
  double worst = 0.0;
  for (const nhc::runtime::SensitivitySample& s : run.samples) {
    const double x = (2 * std::sin(s.t) - std::sin(2 * s.t)) / 3;
    worst = std::max({worst, std::abs(s.y[static_cast<std::size_t>(x0.index)] - x),
                      std::abs(s.s[0][static_cast<std::size_t>(x0.index)] - std::cos(s.t))});
    REQUIRE(s.u.size() == 1);
    CHECK(std::abs(s.u[0] - std::sin(2 * s.t)) < 1e-15);
  }
  CHECK(worst < 1e-8);
}
