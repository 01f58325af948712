// Appell–Hamel under Chetaev's model, integrated from the generated header with nhc::runtime
// (no dlopen): the application side of docs/generated-code.md.
//
// Equations (models.md; k = b/a, v = sqrt(x'^2 + y'^2)), unknowns x, y, z, lambda1:
//   m x'' = −lambda k x'/v,   m y'' = −lambda k y'/v,   m z'' = −m g + lambda,   z' = k v.
// Parameters m = 1, g = 9.81, a = 1, b = 0.5 (examples/appell_hamel.toml).
// Initial data: x = y = z = 0, x' = 1, y' = 0.5; z' and lambda1 from the consistent initialization.
// Solver: IDA, dense LU with the generated Jacobian, rtol 1e-8, atol 1e-10.
// Answer: the horizontal direction is constant, v' = −g k/(1 + k^2), z' = k v, lambda = m g/(1 + k^2),
// the energy is conserved, and v reaches 0 at t* = v0 (a^2 + b^2)/(g a b), where the constraint
// gradient is singular: the runtime must stop there with that diagnosis.
// Checks: states within 100 rtol of the closed form up to 0.9 t*, energy drift < 1e-6, stop within
// 1e-6 of t*. Exit code 0 when all hold.
#include <cmath>
#include <cstdio>
#include <vector>

#include "appell_hamel_chetaev.hpp"
#include "nhc/runtime/runtime.hpp"

namespace gen = nhc_gen::appell_hamel_chetaev;
using namespace nhc::runtime;

int main() {
  const Model model = NHC_RUNTIME_MODEL(gen);
  const std::vector<double> p = model.default_parameters();
  const double m = p[model.parameter_index("m")], g = p[model.parameter_index("g")];
  const double a = p[model.parameter_index("a")], b = p[model.parameter_index("b")];
  const double k = b / a, vx0 = 1.0, vy0 = 0.5, v0 = std::hypot(vx0, vy0);
  const double decel = g * k / (1 + k * k), t_star = v0 * (a * a + b * b) / (g * a * b);

  InitialState initial;
  initial.y.assign(gen::n_states, 0.0);
  initial.given.assign(gen::n_states, false);
  auto give = [&](int variable, int order, double value) {
    const int i = model.state_index(variable, order);
    initial.y[i] = value;
    initial.given[i] = true;
  };
  give(0, 0, 0.0), give(0, 1, vx0), give(1, 0, 0.0), give(1, 1, vy0), give(2, 0, 0.0);

  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  options.linear_solver = LinearSolverKind::dense;

  // Past t*: the run must end at the singular point.
  const RunResult run = simulate(model, p, initial, output_times(0.0, 1.5 * t_star, 300), options);
  bool ok = true;
  double worst = 0;
  for (const Sample& s : run.samples) {
    if (s.t > 0.9 * t_star) break;
    const double arc = v0 * s.t - decel * s.t * s.t / 2, v = v0 - decel * s.t;
    const double exact[gen::n_states] = {vx0 / v0 * arc, vx0 / v0 * v, vy0 / v0 * arc,     vy0 / v0 * v,
                                         k * arc,        k * v,        m * g / (1 + k * k)};
    for (int i = 0; i < gen::n_states; ++i)
      worst = std::max(worst, std::abs(s.y[i] - exact[i]) / std::max(1.0, std::abs(exact[i])));
  }
  const DriftReport drift = measure_drift(model, p, run.samples);
  const Statistics& st = run.statistics;

  std::printf(
      "Appell-Hamel (chetaev): %zu samples, %ld steps, %ld residual and %ld Jacobian evaluations, "
      "%ld error-test and %ld nonlinear failures, %.3f ms\n",
      run.samples.size(), st.steps, st.residual_evaluations, st.jacobian_evaluations, st.error_test_failures,
      st.nonlinear_failures, 1e3 * (st.initialization_seconds + st.integration_seconds));
  std::printf("max relative error vs closed form up to 0.9 t*: %.3e (limit %.1e)\n", worst, 100 * options.rtol);
  std::printf("energy drift: %.3e relative (limit 1e-6); hidden-constraint drift %.3e\n", drift.max_invariant_relative,
              drift.max_hidden);
  ok = ok && worst <= 100 * options.rtol && drift.max_invariant_relative < 1e-6;

  if (!run.failure || run.failure->kind() != nhc::base::FailureKind::singular_constraint_gradient) {
    std::printf("FAIL: expected a stop at the singular constraint gradient, got %s\n",
                run.failure ? run.failure->what() : "no stop");
    return 1;
  }
  std::printf("stop: %s\n", run.failure->what());
  std::printf("t_stop - t* = %.3e (limit 1e-6)\n", run.failure->t() - t_star);
  ok = ok && std::abs(run.failure->t() - t_star) < 1e-6;
  std::printf("%s\n", ok ? "OK" : "FAIL");
  return ok ? 0 : 1;
}
