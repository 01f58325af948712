// Forward sensitivities (runtime/sensitivity.hpp) against central differences of whole runs and
// against the closed form of the knife edge on an incline (examples/knife_edge_incline.toml).
#include <catch2/catch.hpp>

#include <cmath>

#include "nhc/runtime/runtime.hpp"
#include "test_models.hpp"

using namespace nhc;
using runtime::SensitivityParameter;

namespace {

runtime::IntegratorOptions tight() {
  runtime::IntegratorOptions o;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  return o;
}

/// y(t_end) of a plain run.
std::vector<double> final_state(const runtime::Model& model, const std::vector<double>& p,
                                const runtime::InitialState& initial, double t_end) {
  const runtime::RunResult run = runtime::simulate(model, p, initial, {initial.t0, t_end}, tight());
  REQUIRE_FALSE(run.failure);
  REQUIRE(run.samples.back().t == t_end);
  return run.samples.back().y;
}

void check_against_differences(const runtime::Model& model, const runtime::InitialState& initial, double t_end,
                               const std::vector<std::string>& names, const runtime::SensitivityOptions& so) {
  const std::vector<double> p = model.default_parameters();
  std::vector<SensitivityParameter> thetas;
  for (const std::string& name : names) thetas.push_back(runtime::sensitivity_parameter(model, name));
  const runtime::SensitivityRun run =
      runtime::simulate_sensitivities(model, p, initial, thetas, {initial.t0, t_end}, tight(), so);
  REQUIRE_FALSE(run.failure);
  const runtime::SensitivitySample& end = run.samples.back();
  for (size_t k = 0; k < thetas.size(); ++k) {
    const SensitivityParameter& th = thetas[k];
    std::vector<double> p_plus = p, p_minus = p;
    runtime::InitialState plus = initial, minus = initial;
    double& a = th.kind == SensitivityParameter::Kind::parameter ? p_plus[th.index] : plus.y[th.index];
    double& b = th.kind == SensitivityParameter::Kind::parameter ? p_minus[th.index] : minus.y[th.index];
    const double h = 1e-4 * std::max(1.0, std::abs(a));
    a += h;
    b -= h;
    const std::vector<double> yp = final_state(model, p_plus, plus, t_end);
    const std::vector<double> ym = final_state(model, p_minus, minus, t_end);
    double largest = 0, worst = 0;
    for (int i = 0; i < model.n_states(); ++i) {
      if (!model.is_differential(i)) continue;
      largest = std::max(largest, std::abs(end.s[k][i]));
      worst = std::max(worst, std::abs(end.s[k][i] - (yp[i] - ym[i]) / (2 * h)));
    }
    INFO(model.scene_name() << " " << model.model_name() << ": d/d(" << th.name << "), largest " << largest
                            << ", worst difference " << worst);
    CHECK(largest > 0);
    CHECK(worst <= 1e-6 * largest);
  }
}

/// ∂y(t_end)/∂θ from IDAS against (y(θ + h) − y(θ − h)) / 2h, h = 1e-4 max(1, |θ|), on the
/// differential states: relative 1e-6 of the largest sensitivity; with the sensitivities in the
/// error test and without.
void check_against_differences(const runtime::Model& model, const runtime::InitialState& initial, double t_end,
                               const std::vector<std::string>& names) {
  for (const bool error_control : {true, false}) {
    INFO("sensitivity error control " << (error_control ? "on" : "off"));
    runtime::SensitivityOptions so;
    so.error_control = error_control;
    check_against_differences(model, initial, t_end, names, so);
  }
}

runtime::InitialState scene_initial(const std::string& file, const runtime::Model& model) {
  const Scene scene = load_scene(std::string(NHC_SOURCE_DIR) + "/examples/" + file);
  return runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
}

}  // namespace

TEST_CASE("sensitivities of Appell-Hamel (chetaev) match central differences", "[sensitivity]") {
  const auto loaded = test::example_model("appell_hamel.toml", ModelKind::chetaev);
  const runtime::Model& model = loaded.model();
  REQUIRE(model.has_parameter_jacobian());
  check_against_differences(model, scene_initial("appell_hamel.toml", model), 0.2, {"g", "b", "a", "x'(0)", "y(0)"});
}

TEST_CASE("sensitivities of the particle (chetaev) match central differences", "[sensitivity]") {
  const auto loaded = test::example_model("particle.toml", ModelKind::chetaev);
  const runtime::Model& model = loaded.model();
  check_against_differences(model, scene_initial("particle.toml", model), 1.0, {"q1'(0)", "q3'(0)"});
}

TEST_CASE("sensitivities of the vakonomic Heisenberg system match central differences", "[sensitivity]") {
  const auto loaded = test::example_model("heisenberg.toml", ModelKind::vakonomic);
  const runtime::Model& model = loaded.model();
  const Scene scene = load_scene(std::string(NHC_SOURCE_DIR) + "/examples/heisenberg.toml");
  auto values = scene.initial.values;
  values["x"] = {0.0, 1.0};
  values["y"] = {0.0, 0.5};
  values["lambda1"] = {2.0};
  check_against_differences(model, runtime::initial_state_from(model, 0.0, values), 1.0,
                            {"lambda1(0)", "x'(0)", "y'(0)"});
}

TEST_CASE("knife edge on an incline: dx/dalpha and dx/domega in closed form", "[sensitivity]") {
  // x = g sin(alpha)/(2 w^2) sin^2(w t), w = phi'(0):
  //   dx/dalpha = g cos(alpha)/(2 w^2) sin^2(w t),
  //   dx/dw     = g sin(alpha) (t sin(2 w t)/(2 w^2) - sin^2(w t)/w^3).
  const auto loaded = test::example_model("knife_edge_incline.toml", ModelKind::chetaev);
  const runtime::Model& model = loaded.model();
  const double g = 9.81, alpha = 0.3, w = 2.0;
  const std::vector<SensitivityParameter> thetas = {runtime::sensitivity_parameter(model, "alpha"),
                                                    runtime::sensitivity_parameter(model, "phi'(0)")};
  // With the sensitivities outside the error test they rest on their corrector alone: IDAS's own
  // convergence test let them grow to 1e9 by t = 2 here (sensitivity.cpp).
  for (const bool error_control : {true, false}) {
    runtime::SensitivityOptions so;
    so.error_control = error_control;
    const runtime::SensitivityRun run = runtime::simulate_sensitivities(
        model, model.default_parameters(), scene_initial("knife_edge_incline.toml", model), thetas,
        runtime::output_times(0, 2, 40), tight(), so);
    INFO("error control " << (error_control ? "on" : "off"));
    REQUIRE_FALSE(run.failure);
    const int x = model.state_index(0, 0);
    double worst_alpha = 0, worst_omega = 0;
    for (const auto& s : run.samples) {
      const double t = s.t, sw = std::sin(w * t);
      worst_alpha = std::max(worst_alpha, std::abs(s.s[0][x] - g * std::cos(alpha) / (2 * w * w) * sw * sw));
      worst_omega = std::max(
          worst_omega,
          std::abs(s.s[1][x] - g * std::sin(alpha) * (t * std::sin(2 * w * t) / (2 * w * w) - sw * sw / (w * w * w))));
    }
    INFO(worst_alpha << ", " << worst_omega);
    CHECK(worst_alpha < 1e-8);
    CHECK(worst_omega < 1e-8);
  }
}

TEST_CASE("sensitivity names: unknown names and algebraic states are refused in words", "[sensitivity]") {
  const auto loaded = test::example_model("knife_edge_incline.toml", ModelKind::chetaev);
  const runtime::Model& model = loaded.model();
  CHECK_THROWS_WITH(runtime::sensitivity_parameter(model, "beta"), Catch::Contains("unknown parameter beta"));
  CHECK_THROWS_WITH(runtime::sensitivity_parameter(model, "w(0)"), Catch::Contains("unknown initial value w(0)"));
  CHECK_THROWS_WITH(runtime::sensitivity_parameter(model, "lambda1(0)"), Catch::Contains("algebraic state"));
}
