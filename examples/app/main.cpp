// An application around two generated models (nhc_add_model in CMakeLists.txt), integrated
// with nhc::runtime from the compiled-in headers (no dlopen; docs/runtime.md).
//
// 1. Appell–Hamel under Chetaev's model (examples/appell_hamel.toml; models.md). With
//    k = b/a and v = sqrt(x'^2 + y'^2): m x'' = −λ k x'/v, m y'' = −λ k y'/v, m z'' = −m g + λ,
//    z' = k v. From x = y = z = 0, x' = 1, y' = 0.5 the horizontal direction stays fixed,
//    v' = −g k/(1 + k^2), z' = k v, λ = m g/(1 + k^2), and v reaches 0 at
//    t* = v0 (a^2 + b^2)/(g a b), where the constraint gradient is singular: the run must stop
//    there. Checks: states within 100 rtol of the closed form up to 0.9 t*, energy drift < 1e-6,
//    stop within 1e-6 of t*.
// 2. The particle under q'·q'' = 0 (examples/particle.toml), Chetaev: λ = 0 and uniform motion
//    q = q0 + q0' t, here with the sparse Jacobian and KLU. Checks: |q − (t, 2t, 2t)| < 1e-6 on
//    [0, 1], speed drift < 1e-8.
// Solver: IDA, rtol 1e-8, atol 1e-10. Parameters are the scenes' defaults (the header's
// default_parameters). Exit code 0 when every check holds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "appell_hamel_chetaev.hpp"
#include "nhc/runtime/runtime.hpp"
#include "particle_chetaev.hpp"

using namespace nhc::runtime;

namespace {

InitialState initial_state(const Model& model) {
  InitialState s;
  s.y.assign(static_cast<std::size_t>(model.n_states()), 0.0);
  s.given.assign(static_cast<std::size_t>(model.n_states()), false);
  return s;
}

void give(const Model& model, InitialState& s, int variable, int order, double value) {
  const auto i = static_cast<std::size_t>(model.state_index(variable, order));
  s.y[i] = value;
  s.given[i] = true;
}

bool appell_hamel() {
  namespace gen = nhc_gen::appell_hamel_chetaev;
  const Model model = NHC_RUNTIME_MODEL(gen);
  const std::vector<double> p = model.default_parameters();
  const double m = p[static_cast<std::size_t>(model.parameter_index("m"))];
  const double g = p[static_cast<std::size_t>(model.parameter_index("g"))];
  const double a = p[static_cast<std::size_t>(model.parameter_index("a"))];
  const double b = p[static_cast<std::size_t>(model.parameter_index("b"))];
  const double k = b / a, vx0 = 1.0, vy0 = 0.5, v0 = std::hypot(vx0, vy0);
  const double decel = g * k / (1 + k * k), t_star = v0 * (a * a + b * b) / (g * a * b);

  InitialState s = initial_state(model);
  give(model, s, 0, 0, 0.0), give(model, s, 0, 1, vx0), give(model, s, 1, 0, 0.0), give(model, s, 1, 1, vy0);
  give(model, s, 2, 0, 0.0);
  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  options.linear_solver = LinearSolverKind::dense;

  const RunResult run = simulate(model, p, s, output_times(0.0, 1.5 * t_star, 300), options);
  double worst = 0;
  for (const Sample& sample : run.samples) {
    if (sample.t > 0.9 * t_star) break;
    const double t = sample.t, arc = v0 * t - decel * t * t / 2, v = v0 - decel * t;
    const double exact[] = {vx0 / v0 * arc, vx0 / v0 * v, vy0 / v0 * arc,     vy0 / v0 * v,
                            k * arc,        k * v,        m * g / (1 + k * k)};
    for (int i = 0; i < gen::n_states; ++i)
      worst = std::max(worst,
                       std::abs(sample.y[static_cast<std::size_t>(i)] - exact[i]) / std::max(1.0, std::abs(exact[i])));
  }
  const DriftReport drift = measure_drift(model, p, run.samples);
  std::printf("appell_hamel chetaev: %d states, b = %.17g, %zu samples, %ld steps\n", gen::n_states, b,
              run.samples.size(), run.statistics.steps);
  std::printf("appell_hamel max_relative_error = %.3e (limit %.1e)\n", worst, 100 * options.rtol);
  std::printf("appell_hamel energy_drift = %.3e (limit 1e-6)\n", drift.max_invariant_relative);
  bool ok = worst <= 100 * options.rtol && drift.max_invariant_relative < 1e-6;
  if (!run.failure || run.failure->kind() != nhc::base::FailureKind::singular_constraint_gradient) {
    std::printf("appell_hamel FAIL: expected a stop at the singular constraint gradient, got %s\n",
                run.failure ? run.failure->what() : "no stop");
    return false;
  }
  std::printf("appell_hamel stop: %s\n", run.failure->what());
  std::printf("appell_hamel t_stop = %.12f t_star = %.12f\n", run.failure->t(), t_star);
  ok = ok && std::abs(run.failure->t() - t_star) < 1e-6;
  std::printf("appell_hamel %s\n", ok ? "OK" : "FAIL");
  return ok;
}

bool particle() {
  namespace gen = nhc_gen::particle_chetaev;
  const Model model = NHC_RUNTIME_MODEL(gen);
  const std::vector<double> p = model.default_parameters();
  const double velocity[] = {1.0, 2.0, 2.0};
  InitialState s = initial_state(model);
  for (int c = 0; c < 3; ++c) give(model, s, c, 0, 0.0), give(model, s, c, 1, velocity[c]);
  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  options.linear_solver = LinearSolverKind::sparse;

  const RunResult run = simulate(model, p, s, output_times(0.0, 1.0, 100), options);
  double worst = 0;
  for (const Sample& sample : run.samples)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst,
                       std::abs(sample.y[static_cast<std::size_t>(model.state_index(c, 0))] - velocity[c] * sample.t));
  const DriftReport drift = measure_drift(model, p, run.samples);
  const double t_end = run.samples.empty() ? 0.0 : run.samples.back().t;
  std::printf("particle chetaev: %d states, sparse Jacobian (%d nonzeros), %zu samples to t = %g, %ld steps\n",
              gen::n_states, gen::jacobian_nnz, run.samples.size(), t_end, run.statistics.steps);
  std::printf("particle max_position_error = %.3e (limit 1e-6)\n", worst);
  std::printf("particle speed_drift = %.3e (limit 1e-8)\n", drift.max_invariant_relative);
  const bool ok = !run.failure && t_end == 1.0 && worst < 1e-6 && drift.max_invariant_relative < 1e-8;
  if (run.failure) std::printf("particle failure: %s\n", run.failure->what());
  std::printf("particle %s\n", ok ? "OK" : "FAIL");
  return ok;
}

}  // namespace

int main() {
#ifdef NHC_PACKAGE_VERSION
  std::printf("nhc package %s\n", NHC_PACKAGE_VERSION);
#endif
  const bool ok = appell_hamel() & particle();
  std::printf("%s\n", ok ? "OK" : "FAIL");
  return ok ? 0 : 1;
}
