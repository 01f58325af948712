// A scene built in code, compiled and loaded in-process by nhc::jit (docs/library.md), integrated
// by nhc::runtime and checked against the closed form — twice, for two scenes of the same name
// (one generated namespace) with different b: each must give its own answer.
//
// Appell–Hamel under Chetaev's model (models.md; k = b/a, v = |(x', y')|): from x = y = z = 0,
// x' = 1, y' = 0.5 the horizontal direction stays fixed, v = v0 − g k t/(1 + k^2), z' = k v,
// λ = m g/(1 + k^2), and v reaches 0 at t* = v0 (a^2 + b^2)/(g a b). Checks on [0, 0.9 t*]:
// every state within 100 rtol of the closed form. Exit code 0 when both scenes pass and their
// tables are distinct.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "nhc/codegen.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"

namespace {

constexpr double m = 1.0, g = 9.81, a = 1.0, vx0 = 1.0, vy0 = 0.5;

nhc::Scene appell_hamel(double b) {
  return nhc::SceneBuilder("appell_hamel")
      .coordinates({"x", "y", "z"})
      .parameter("m", m)
      .parameter("g", g)
      .parameter("a", a)
      .parameter("b", b)
      .lagrangian("m/2*(x'^2 + y'^2 + z'^2) - m*g*z")
      .constraint("z' - b/a*sqrt(x'^2 + y'^2)")
      .initial("x", {0.0, vx0})
      .initial("y", {0.0, vy0})
      .initial("z", {0.0})
      .build();
}

/// Integrates the loaded model to 0.9 t* and prints the worst relative error against the closed
/// form; returns whether it is within 100 rtol.
bool check(const nhc::Scene& scene, const nhc::runtime::Model& model, double b) {
  using namespace nhc::runtime;
  const double k = b / a, v0 = std::hypot(vx0, vy0), decel = g * k / (1 + k * k);
  const double t_star = v0 * (a * a + b * b) / (g * a * b), t_end = 0.9 * t_star;
  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, scene.initial.t0, scene.initial.values),
               output_times(0.0, t_end, 100), options);
  if (run.failure) {
    std::printf("jit b = %g FAIL: %s\n", b, run.failure->what());
    return false;
  }
  double worst = 0;
  for (const Sample& sample : run.samples) {
    const double t = sample.t, arc = v0 * t - decel * t * t / 2, v = v0 - decel * t;
    const double exact[] = {vx0 / v0 * arc, vx0 / v0 * v, vy0 / v0 * arc,     vy0 / v0 * v,
                            k * arc,        k * v,        m * g / (1 + k * k)};
    for (int i = 0; i < 7; ++i)
      worst = std::max(worst,
                       std::abs(sample.y[static_cast<std::size_t>(i)] - exact[i]) / std::max(1.0, std::abs(exact[i])));
  }
  const double z_dot = run.samples.back().y[static_cast<std::size_t>(model.state_index(2, 1))];
  const bool ok = worst <= 100 * options.rtol && run.samples.back().t == t_end;
  std::printf("jit b = %g: t_end = %.12f z'(t_end) = %.12f (exact %.12f) max_relative_error = %.3e %s\n", b, t_end,
              z_dot, k * (v0 - decel * t_end), worst, ok ? "OK" : "FAIL");
  return ok;
}

}  // namespace

int main() {
  try {
    const nhc::Scene first = appell_hamel(0.5), second = appell_hamel(0.25);
    const nhc::jit::LoadedModel one = nhc::jit::build(first, nhc::ModelKind::chetaev);
    const nhc::jit::LoadedModel two = nhc::jit::build(second, nhc::ModelKind::chetaev);
    const bool distinct = &one.model().table() != &two.model().table();
    std::printf("jit: two scenes named %s, libraries %s and %s, tables %s\n", first.name.c_str(),
                one.library().path.filename().c_str(), two.library().path.filename().c_str(),
                distinct ? "distinct" : "SHARED");
    const bool ok = distinct & check(first, one.model(), 0.5) & check(second, two.model(), 0.25);
    std::printf("jit %s\n", ok ? "OK" : "FAIL");
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("jit FAIL: %s\n", e.what());
    return 1;
  }
}
