// The interpreted model against the compiled one (docs/interpreter.md): per call of the
// residual and the Jacobian, a whole run, and the cold start (derive + generate + interpret, or
// + compile into an empty cache) — side by side in one process, one Markdown row per scene; and
// per call against the header compiled at -O2 (the policy compiles long headers at -O0).
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

/// Seconds per call of each of `fs`: batches of at least 0.05 s, the batches of all functions
/// interleaved (a change of the machine's load hits all alike), best of 15 rounds.
std::vector<double> per_call(const std::vector<std::function<void()>>& fs) {
  std::vector<long> calls(fs.size(), 1);
  for (std::size_t i = 0; i < fs.size(); ++i)
    for (;;) {
      const auto start = Clock::now();
      for (long k = 0; k < calls[i]; ++k) fs[i]();
      const double s = seconds_since(start);
      if (s >= 0.05) break;
      calls[i] *= s > 0 ? std::max(2L, static_cast<long>(0.05 / s * 1.2)) : 10;
    }
  std::vector<double> best(fs.size(), 1e300);
  for (int round = 0; round < 15; ++round)
    for (std::size_t i = 0; i < fs.size(); ++i) {
      const auto start = Clock::now();
      for (long k = 0; k < calls[i]; ++k) fs[i]();
      best[i] = std::min(best[i], seconds_since(start) / static_cast<double>(calls[i]));
    }
  return best;
}

struct Measured {
  double cold = 0, residual = 0, jacobian = 0, run = 1e300;
  int states = 0;
};

/// Builds the scene's model cold (an empty cache, no scene cache); `optimized`: the header
/// compiled at -O2 whatever its length (the policy compiles long headers at -O0).
nhc::jit::LoadedModel build_cold(const nhc::Scene& scene, nhc::jit::Backend backend, const fs::path& cache,
                                 bool optimized, double& seconds) {
  fs::remove_all(cache);
  nhc::jit::BuildOptions options;
  options.backend = backend;
  if (optimized) options.compile.long_header_bytes = 0;
  options.scene_cache = false;
  options.compile.cache_directory = cache;
  const auto start = Clock::now();
  nhc::jit::LoadedModel built = nhc::jit::build(scene, scene.simulate.model.value_or(nhc::ModelKind::chetaev), options);
  seconds = seconds_since(start);
  return built;
}

/// The models' residual and Jacobian per call, interleaved, and their whole runs to t_end,
/// alternating (best of 5 each).
std::vector<Measured> measure(const nhc::Scene& scene, const std::vector<const nhc::runtime::Model*>& models) {
  std::vector<Measured> out(models.size());
  struct Buffers {
    std::vector<double> y, yp, r, J, pu;
  };
  std::vector<Buffers> buffers(models.size());
  std::vector<std::function<void()>> fs;
  for (std::size_t m = 0; m < models.size(); ++m) {
    const nhc::runtime::Model& model = *models[m];
    const auto n = static_cast<std::size_t>(model.n_states());
    Buffers& b = buffers[m];
    b.y.assign(n, 0.5);
    b.yp.assign(n, 0.25);
    b.r.assign(n, 0.0);
    b.J.assign(n * n + 1 + static_cast<std::size_t>(model.table().jacobian_nnz), 0.0);
    b.pu = model.default_parameters();
    b.pu.resize(b.pu.size() + static_cast<std::size_t>(model.n_inputs()), 0.0);
    b.pu.push_back(0.0);
    const nhc_model_table& t = model.table();
    out[m].states = model.n_states();
    fs.push_back([&t, &b] { t.residual(0.1, b.y.data(), b.yp.data(), b.pu.data(), b.r.data()); });
    fs.push_back([&t, &b] {
      if (t.jacobian) t.jacobian(0.1, b.y.data(), b.yp.data(), 10.0, b.pu.data(), b.J.data());
      else if (t.jacobian_values) t.jacobian_values(0.1, b.y.data(), b.yp.data(), 10.0, b.pu.data(), b.J.data());
    });
  }
  const std::vector<double> seconds = per_call(fs);
  for (std::size_t m = 0; m < models.size(); ++m) {
    out[m].residual = seconds[2 * m];
    out[m].jacobian = seconds[2 * m + 1];
  }
  nhc::runtime::IntegratorOptions io;
  io.rtol = scene.simulate.rtol;
  io.atol = scene.simulate.atol;
  for (int k = 0; k < 5; ++k)
    for (std::size_t m = 0; m < models.size(); ++m) {
      const nhc::runtime::Model& model = *models[m];
      const nhc::runtime::InitialState initial =
          nhc::runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
      const auto run_start = Clock::now();
      const nhc::runtime::RunResult run =
          nhc::runtime::simulate(model, model.default_parameters(), initial,
                                 nhc::runtime::output_times(scene.initial.t0, scene.simulate.t_end, 100), io);
      out[m].run = std::min(out[m].run, seconds_since(run_start));
      if (run.failure) std::cerr << scene.name << ": the run failed at t = " << run.samples.back().t << "\n";
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: nhc_interpreter_bench SCENE...\n";
    return 2;
  }
  const fs::path cache = fs::temp_directory_path() / "nhc-interpreter-bench";
  std::cout << "| scene | states | residual: interpreted / compiled | Jacobian: interpreted / compiled "
               "| run (t_end): interpreted / compiled | cold build: interpreted / compiled "
               "| compiled at -O2 (when the policy chose -O0): residual, Jacobian, interpreted / it |\n"
            << "|---|---|---|---|---|---|---|\n";
  for (int i = 1; i < argc; ++i) {
    const nhc::Scene scene = nhc::load_scene(argv[i]);
    double cold_a = 0, cold_b = 0, cold_c = 0;
    const nhc::jit::LoadedModel ia = build_cold(scene, nhc::jit::Backend::interpreted, cache, false, cold_a);
    const nhc::jit::LoadedModel ib = build_cold(scene, nhc::jit::Backend::compiled, cache / "policy", false, cold_b);
    const nhc::jit::LoadedModel ic = build_cold(scene, nhc::jit::Backend::compiled, cache / "o2", true, cold_c);
    const std::vector<Measured> all = measure(scene, {&ia.model(), &ib.model(), &ic.model()});
    Measured a = all[0], b = all[1];
    const Measured c = all[2];
    a.cold = cold_a;
    b.cold = cold_b;
    const nhc::Scene& s = scene;
    std::cout << fmt::format(
        "| {} | {} | {:.3g} µs / {:.3g} µs ({:.1f}×) | {:.3g} µs / {:.3g} µs ({:.1f}×) | {:.3g} s / {:.3g} s ({:.1f}×, "
        "t_end {}) "
        "| {:.2f} s / {:.2f} s | {:.3g} µs, {:.3g} µs ({:.1f}×, {:.1f}×) |\n",
        s.name, a.states, a.residual * 1e6, b.residual * 1e6, a.residual / b.residual, a.jacobian * 1e6,
        b.jacobian * 1e6, b.jacobian > 0 ? a.jacobian / b.jacobian : 0.0, a.run, b.run, a.run / b.run, s.simulate.t_end,
        a.cold, b.cold, c.residual * 1e6, c.jacobian * 1e6, a.residual / c.residual,
        c.jacobian > 0 ? a.jacobian / c.jacobian : 0.0);
    std::cout.flush();
  }
  fs::remove_all(cache);
  return 0;
}
