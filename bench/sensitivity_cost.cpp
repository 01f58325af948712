// The cost of forward sensitivities: a scene's plain run against the same run with
// one sensitivity per named parameter (initialization and integration; the model is built once,
// with dF/dp).
//
//   python3 bench/knife_chain.py /tmp/kc 16
//   build/bench/nhc_sensitivity_cost /tmp/kc/knife_chain_16.toml alpha [g k ...] [--repeats 21]
//
// The plain run and the run with sensitivities alternate, `repeats` times each, so that a change
// of the machine's load hits both alike; each is timed by the wall clock and by the thread's CPU
// clock (which other processes on a shared machine disturb less). Prints the medians and their
// ratio per measurement; bench/sensitivity.md records the numbers.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Wall and CPU seconds of `run`, appended to the two lists.
struct Timings {
  std::vector<double> wall, cpu;
  template <class Run>
  void measure(Run&& run) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    run();
    cpu.push_back(cpu_seconds() - cpu_start);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: nhc_sensitivity_cost SCENE NAME... [--repeats R]\n";
    return 2;
  }
  std::vector<std::string> names;
  int repeats = 21;
  for (int k = 2; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--repeats" && k + 1 < argc) repeats = std::max(1, std::stoi(argv[++k]));
    else names.push_back(arg);
  }
  const nhc::Scene scene = nhc::load_scene(argv[1]);
  nhc::jit::BuildOptions options;
  options.sensitivities = true;
  const auto loaded = nhc::jit::build(scene, nhc::model_or_default(scene, ""), options);
  const nhc::runtime::Model& model = loaded.model();
  const auto initial = nhc::runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
  const auto times = nhc::runtime::output_times(scene.initial.t0, scene.simulate.t_end, 200);
  nhc::runtime::IntegratorOptions io;
  io.rtol = scene.simulate.rtol;
  io.atol = scene.simulate.atol;
  const std::vector<double> p = model.default_parameters();

  long plain_steps = 0;
  const auto plain_run = [&] {
    const auto run = nhc::runtime::simulate(model, p, initial, times, io);
    if (run.failure) throw *run.failure;
    plain_steps = run.statistics.steps;
  };
  std::cout << scene.name << ": " << model.n_states() << " states, " << repeats
            << " alternating runs per line (median wall / median CPU time)\n";
  for (bool error_control : {true, false}) {
    std::vector<nhc::runtime::SensitivityParameter> thetas;
    for (const std::string& name : names) {
      thetas.push_back(nhc::runtime::sensitivity_parameter(model, name));
      nhc::runtime::SensitivityOptions so;
      so.error_control = error_control;
      long steps = 0, residuals = 0;
      Timings plain, with;
      for (int r = 0; r < repeats; ++r) {
        plain.measure(plain_run);
        with.measure([&] {
          const auto run = nhc::runtime::simulate_sensitivities(model, p, initial, thetas, times, io, so);
          if (run.failure) throw *run.failure;
          steps = run.statistics.state.steps;
          residuals = run.statistics.sensitivity_residual_evaluations;
        });
      }
      std::cout << "  " << thetas.size() << " sensitivit" << (thetas.size() == 1 ? "y" : "ies") << " (up to " << name
                << "), error control " << (error_control ? "on " : "off") << ": " << median(with.wall) * 1e3 << " / "
                << median(with.cpu) * 1e3 << " ms = " << median(with.wall) / median(plain.wall) << " / "
                << median(with.cpu) / median(plain.cpu) << " x plain (" << median(plain.wall) * 1e3 << " / "
                << median(plain.cpu) * 1e3 << " ms); " << steps << " steps (plain " << plain_steps << "), " << residuals
                << " sensitivity residuals\n";
    }
  }
  return 0;
}
