// The C++ side of the Python overhead benchmark (bench/python_overhead.py): `runs`
// integrations of a scene's model from its [initial], in a loop, as Model.simulate of the Python
// package runs them (runtime::simulate, the same options and output times), timed in-process.
//
//   build-bench/bench/nhc_python_overhead examples/knife_edge.toml --runs 200 --t-end 1 --outputs 200
//
// Prints one JSON line: the loop's wall seconds for runtime::simulate alone ("simulate") and for
// runtime::simulate followed by what a Python Run is given besides the samples — the CSV rows
// as a matrix and the drift report ("simulate_rows_drift").
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: nhc_python_overhead SCENE [--runs R] [--t-end T] [--outputs N] [--rtol R] [--atol A]\n";
    return 2;
  }
  int runs = 200, outputs = 200;
  double t_end = 1.0, rtol = 1e-8, atol = 1e-10;
  for (int k = 2; k + 1 < argc; k += 2) {
    const std::string flag = argv[k];
    const char* value = argv[k + 1];
    if (flag == "--runs") runs = std::atoi(value);
    else if (flag == "--t-end") t_end = std::atof(value);
    else if (flag == "--outputs") outputs = std::atoi(value);
    else if (flag == "--rtol") rtol = std::atof(value);
    else if (flag == "--atol") atol = std::atof(value);
    else {
      std::cerr << "nhc_python_overhead: unknown flag " << flag << "\n";
      return 2;
    }
  }
  const nhc::Scene scene = nhc::load_scene(argv[1]);
  const nhc::jit::LoadedModel loaded = nhc::jit::build(scene, nhc::model_or_default(scene, ""));
  const nhc::runtime::Model& model = loaded.model();
  const std::vector<double> p = model.default_parameters();
  nhc::runtime::IntegratorOptions options;
  options.rtol = rtol;
  options.atol = atol;
  const double t0 = scene.initial.t0;

  // Model.simulate's C++ part: the output times, the initial state, the run.
  const auto one_run = [&] {
    const std::vector<double> times = nhc::runtime::output_times(t0, t_end, outputs);
    nhc::runtime::RunResult run = nhc::runtime::simulate(
        model, p, nhc::runtime::initial_state_from(model, t0, scene.initial.values), times, options);
    if (run.failure) throw *run.failure;
    return run;
  };
  long steps = 0;
  auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < runs; ++r) steps = one_run().statistics.steps;
  const double simulate_seconds = seconds_since(start);

  double checksum = 0;  // keeps the rows and the drift from being optimized away
  start = std::chrono::steady_clock::now();
  for (int r = 0; r < runs; ++r) {
    const nhc::runtime::RunResult run = one_run();
    const nhc::runtime::CsvRows csv(model, p);
    std::vector<double> values, matrix;
    for (const nhc::runtime::Sample& s : run.samples) {
      csv.row(s, values);
      matrix.insert(matrix.end(), values.begin(), values.end());
    }
    checksum += matrix.back() + nhc::runtime::measure_drift(model, p, run.samples).max_hidden;
  }
  const double rows_seconds = seconds_since(start);
  std::cout << "{\"runs\": " << runs << ", \"steps\": " << steps << ", \"states\": " << model.n_states()
            << ", \"simulate\": " << simulate_seconds << ", \"simulate_rows_drift\": " << rows_seconds
            << ", \"checksum\": " << checksum << "}\n";
  return 0;
}
