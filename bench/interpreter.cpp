// The interpreted model against the compiled one (issue 50, docs/interpreter.md): per call of the
// residual and the Jacobian, a whole run, and the cold start (derive + generate + interpret, or
// + compile into an empty cache) — side by side in one process, one Markdown row per scene.
// Usage: nhc_interpreter_bench SCENE... (each with its [simulate] model and t_end)
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Seconds per call of f: batches of at least 0.2 s, best of 5.
double per_call(const std::function<void()>& f) {
  long calls = 1;
  for (;;) {
    const auto start = Clock::now();
    for (long k = 0; k < calls; ++k) f();
    const double s = seconds_since(start);
    if (s >= 0.2) break;
    calls *= s > 0 ? std::max(2L, static_cast<long>(0.2 / s * 1.2)) : 10;
  }
  double best = 1e300;
  for (int round = 0; round < 5; ++round) {
    const auto start = Clock::now();
    for (long k = 0; k < calls; ++k) f();
    best = std::min(best, seconds_since(start) / static_cast<double>(calls));
  }
  return best;
}

struct Measured {
  double cold = 0, residual = 0, jacobian = 0, run = 0;
  int states = 0;
};

Measured measure(const nhc::Scene& scene, nhc::jit::Backend backend, const fs::path& cache) {
  fs::remove_all(cache);
  nhc::jit::BuildOptions options;
  options.backend = backend;
  options.scene_cache = false;
  options.compile.cache_directory = cache;
  const auto start = Clock::now();
  const nhc::jit::LoadedModel built = nhc::jit::build(scene, scene.simulate.model.value_or(nhc::ModelKind::chetaev), options);
  Measured m;
  m.cold = seconds_since(start);
  m.states = built.model().n_states();
  const nhc::runtime::Model& model = built.model();
  const auto n = static_cast<std::size_t>(model.n_states());
  const std::vector<double> p = model.default_parameters();
  const nhc::runtime::InitialState initial = nhc::runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
  std::vector<double> y(n, 0.5), yp(n, 0.25), r(n), J(n * n + 1 + static_cast<std::size_t>(model.table().jacobian_nnz));
  std::vector<double> pu = p;
  pu.resize(p.size() + static_cast<std::size_t>(model.n_inputs()), 0.0);
  pu.push_back(0.0);
  const nhc_model_table& t = model.table();
  m.residual = per_call([&] { t.residual(0.1, y.data(), yp.data(), pu.data(), r.data()); });
  m.jacobian = per_call([&] {
    if (t.jacobian) t.jacobian(0.1, y.data(), yp.data(), 10.0, pu.data(), J.data());
    else if (t.jacobian_values) t.jacobian_values(0.1, y.data(), yp.data(), 10.0, pu.data(), J.data());
  });
  nhc::runtime::IntegratorOptions io;
  io.rtol = scene.simulate.rtol;
  io.atol = scene.simulate.atol;
  double best = 1e300;
  for (int k = 0; k < 3; ++k) {
    const auto run_start = Clock::now();
    const nhc::runtime::RunResult run = nhc::runtime::simulate(
        model, p, initial, nhc::runtime::output_times(scene.initial.t0, scene.simulate.t_end, 100), io);
    best = std::min(best, seconds_since(run_start));
    if (run.failure) std::cerr << scene.name << ": the run failed at t = " << run.samples.back().t << "\n";
  }
  m.run = best;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: nhc_interpreter_bench SCENE...\n";
    return 2;
  }
  const fs::path cache = fs::temp_directory_path() / "nhc-interpreter-bench";
  std::cout << "| scene | states | residual: interpreted / compiled | Jacobian: interpreted / compiled "
               "| run (t_end): interpreted / compiled | cold build: interpreted / compiled |\n"
            << "|---|---|---|---|---|---|\n";
  for (int i = 1; i < argc; ++i) {
    const nhc::Scene scene = nhc::load_scene(argv[i]);
    const Measured a = measure(scene, nhc::jit::Backend::interpreted, cache);
    const Measured b = measure(scene, nhc::jit::Backend::compiled, cache);
    const nhc::Scene& s = scene;
    std::cout << fmt::format(
        "| {} | {} | {:.3g} µs / {:.3g} µs ({:.1f}×) | {:.3g} µs / {:.3g} µs ({:.1f}×) | {:.3g} s / {:.3g} s ({:.1f}×, t_end {}) "
        "| {:.2f} s / {:.2f} s |\n",
        s.name, a.states, a.residual * 1e6, b.residual * 1e6, a.residual / b.residual, a.jacobian * 1e6,
        b.jacobian * 1e6, b.jacobian > 0 ? a.jacobian / b.jacobian : 0.0, a.run, b.run, a.run / b.run, s.simulate.t_end,
        a.cold, b.cold);
    std::cout.flush();
  }
  fs::remove_all(cache);
  return 0;
}
