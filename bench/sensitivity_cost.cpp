// The cost of forward sensitivities (issue 20): a scene's plain run against the same run with
// one sensitivity per named parameter, each the median wall time of `repeats` runs
// (initialization and integration; the model is built once, with dF/dp).
//
//   python3 bench/knife_chain.py /tmp/kc 16
//   build/bench/nhc_sensitivity_cost /tmp/kc/knife_chain_16.toml alpha [g k ...] [--repeats 21]
//
// Prints one line per measurement; bench/sensitivity.md records the numbers.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"

namespace {

template <class Run>
double median_seconds(int repeats, Run&& run) {
  std::vector<double> times;
  for (int k = 0; k < repeats; ++k) {
    const auto start = std::chrono::steady_clock::now();
    run();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

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
    if (arg == "--repeats" && k + 1 < argc) repeats = std::stoi(argv[++k]);
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
  io.progress = false;
  const std::vector<double> p = model.default_parameters();

  long plain_steps = 0;
  const double plain = median_seconds(repeats, [&] {
    const auto run = nhc::runtime::simulate(model, p, initial, times, io);
    if (run.failure) throw *run.failure;
    plain_steps = run.statistics.steps;
  });
  std::cout << scene.name << ": " << model.n_states() << " states; plain run " << plain * 1e3 << " ms (median of "
            << repeats << "), " << plain_steps << " steps\n";
  for (bool error_control : {true, false}) {
    std::vector<nhc::runtime::SensitivityParameter> thetas;
    for (const std::string& name : names) {
      thetas.push_back(nhc::runtime::sensitivity_parameter(model, name));
      nhc::runtime::SensitivityOptions so;
      so.error_control = error_control;
      long steps = 0;
      const double with = median_seconds(repeats, [&] {
        const auto run = nhc::runtime::simulate_sensitivities(model, p, initial, thetas, times, io, so);
        if (run.failure) throw *run.failure;
        steps = run.statistics.state.steps;
      });
      std::cout << "  " << thetas.size() << " sensitivit" << (thetas.size() == 1 ? "y" : "ies") << " (up to " << name
                << "), error control " << (error_control ? "on " : "off") << ": " << with * 1e3 << " ms = "
                << with / plain << " x plain, " << steps << " steps\n";
    }
  }
  return 0;
}
