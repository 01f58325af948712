// nhc simulate SCENE [--model M] [--t-end T] [--rtol R] [--atol A] [--project] [--sensitivity NAMES] [-o FILE.csv]
//              [--plot DIR [--plot-xy a,b]]
//
// The whole pipeline on one model: derive, reduce to index 1, generate the header
// (docs/generated-code.md), compile it with the C++ compiler found at configure time into a
// cached shared object, load it, integrate with nhc::runtime (IDA), write the CSV and print a
// summary. Numerical failures (the Appell–Hamel stop at t*, singular iteration matrices, NaN)
// end with a diagnostic naming t and exit code 3; the CSV then holds the solution up to there.
#include <cmath>
#include <iostream>

#include "commands.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/tolerances.hpp"
#include "pipeline.hpp"
#include "trajectory_plots.hpp"
#include "sensitivity_option.hpp"

namespace nhc::cli {

namespace {

struct SimulateOptions {
  std::string scene_path;
  std::string model;
  std::optional<double> t_end, rtol, atol;
  bool project = false;
  int outputs = 200;
  std::string output;
  std::string plot, plot_xy;  // trajectory_plots.hpp
  SensitivityRequest sensitivity;
};

std::string format(double v, int precision = 3) { return format_number(v, precision); }

/// The flags that override [simulate]: finite, tolerances positive, t_end after t0.
void check_simulate_flags(const SimulateOptions& options, const Scene& scene) {
  auto bad = [&](const std::string& message) { throw InputError({options.scene_path, 0, 0}, message); };
  if (options.t_end) {
    if (!std::isfinite(*options.t_end)) bad("--t-end must be a finite number");
    if (!(*options.t_end > scene.initial.t0))
      bad("--t-end " + format(*options.t_end, 17) + " must be after t0 = " + format(scene.initial.t0, 17));
  }
  if (options.rtol && !relative_tolerance_problem(*options.rtol).empty())
    throw InputError({"--rtol", 0, 0}, "--rtol " + format(*options.rtol) + " " + relative_tolerance_problem(*options.rtol));
  if (options.atol && !(std::isfinite(*options.atol) && *options.atol > 0)) bad("--atol must be a positive number");
}

}  // namespace

CommandRunner add_simulate_command(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate", "derive, generate, compile and integrate one model of a scene with SUNDIALS IDA");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--t-end", options->t_end, "final time (default: [simulate] t_end)");
  sub->add_option("--rtol", options->rtol, "relative tolerance (default: [simulate] rtol)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--atol", options->atol, "absolute tolerance (default: [simulate] atol)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--project", options->project, "project onto the hidden constraints (docs/projection.md)");
  sub->add_option("--outputs", options->outputs, "number of output intervals (default 200)")
      ->check(CLI::Range(1, 10000000));
  sub->add_option("-o,--output", options->output, "CSV file for the solution");
  CLI::Option* plot = sub->add_option(
      "--plot", options->plot, "directory for plots (SVG, PNG) of the coordinates, path, multipliers and drift");
  sub->add_option("--plot-xy", options->plot_xy, "a,b: the plane of the path plot (default: the first two coordinates)")
      ->needs(plot);
  add_sensitivity_options(sub, options->sensitivity);

  return [options]() {
    // Derive, reduce, generate (dense Jacobian; sparse from 40 states), compile (or reuse), load.
    const auto load_start = Clock::now();
    const Scene scene = load_scene(options->scene_path);
    const ModelKind kind = model_or_default(scene, options->model);
    check_simulate_flags(*options, scene);  // before anything is compiled or written
    if (!options->output.empty()) check_output_file(options->output, {options->scene_path});
    PathPlane plane;
    if (!options->plot.empty()) require_gnuplot("--plot"), plane = path_plane(scene, options->plot_xy, "--plot-xy");
    const double load_seconds = seconds_since(load_start);
    jit::BuildOptions build_options;
    build_options.sensitivities = !options->sensitivity.names.empty();
    const jit::LoadedModel built = jit::build(scene, kind, build_options);
    if (build_options.sensitivities) parse_sensitivities(built.model(), options->sensitivity.names);
    const runtime::Model& model = built.model();
    const double derive_seconds = load_seconds + built.timings().derive + built.timings().generate;
    const double compile_seconds = built.timings().compile + built.timings().load;

    // Integrate.
    runtime::IntegratorOptions io;
    io.rtol = options->rtol.value_or(scene.simulate.rtol);
    io.atol = options->atol.value_or(scene.simulate.atol);
    io.projection = options->project ? runtime::ProjectionMethod::in_place : runtime::ProjectionMethod::none;
    io.progress = true;
    const double t0 = scene.initial.t0, t_end = options->t_end.value_or(scene.simulate.t_end);
    if (!(t_end > t0))
      throw InputError({options->scene_path, 0, 0}, "--t-end " + format(t_end, 17) + " must be after t0 = " + format(t0, 17));
    const std::vector<double> p = model.default_parameters();
    const std::vector<double> times = runtime::output_times(t0, t_end, options->outputs);
    const runtime::RunResult run = runtime::simulate(model, p, initial_state_of(scene, model), times, io);
    std::optional<runtime::SensitivityRun> sensitivities;  // --sensitivity: the CSV comes from this run
    if (build_options.sensitivities)
      sensitivities = run_sensitivities(model, p, initial_state_of(scene, model), times, io, options->sensitivity);
    if (!options->output.empty())
      write_file_atomically(options->output, [&](std::ostream& out) {
        if (sensitivities)
          runtime::write_sensitivity_csv(out, model, p, parse_sensitivities(model, options->sensitivity.names),
                                         sensitivities->samples);
        else
          runtime::write_csv(out, model, p, run.samples);
      });

    // Summary.
    const runtime::Statistics& st = run.statistics;
    const runtime::DriftReport drift = runtime::measure_drift(model, p, run.samples);
    std::cout << "nhc simulate: " << scene.name << ", model " << to_string(kind) << ", t from " << t0 << " to "
              << (run.samples.empty() ? t0 : run.samples.back().t) << " (of " << t_end << "), rtol " << io.rtol
              << ", atol " << io.atol << (options->project ? ", projection" : "") << "\n"
              << "  steps " << st.steps << ", residual evaluations " << st.residual_evaluations
              << ", Jacobian evaluations " << st.jacobian_evaluations << " (" << st.linear_solver << ", "
              << st.jacobian << "), error-test failures " << st.error_test_failures << ", nonlinear failures "
              << st.nonlinear_failures;
    if (options->project) std::cout << ", projections " << st.projections;
    std::cout << "\n  time: derive " << format(derive_seconds) << " s, compile " << format(compile_seconds) << " s"
              << (built.library().reused ? " (cached)" : "") << ", integrate "
              << format(st.initialization_seconds + st.integration_seconds) << " s\n";
    if (sensitivities) std::cout << describe_sensitivity_cost(*sensitivities, options->sensitivity, st);
    if (model.n_reference() > 0) std::cout << "  max reference error " << format(drift.max_error) << "\n";
    if (model.n_hidden() > 0) std::cout << "  max hidden-constraint drift " << format(drift.max_hidden) << "\n";
    for (int k = 0; k < model.n_invariants(); ++k)
      std::cout << "  invariant " << model.table().invariant_names[k] << ": max drift "
                << format(drift.invariant_drift[k]) << " (relative " << format(drift.invariant_relative[k]) << ")\n";
    if (!options->output.empty())
      std::cout << "  wrote " << options->output << " ("
                << (sensitivities ? sensitivities->samples.size() : run.samples.size()) << " rows)\n";
    if (sensitivities && sensitivities->failure && !run.failure) {
      std::cout.flush();
      std::cerr << "nhc: error: sensitivities: " << sensitivities->failure->what() << "\n";
      return kExitMathFailure;
    }
    if (!options->plot.empty() && run.samples.empty()) std::cout << "  no plots: the run did not get past t0\n";
    if (!options->plot.empty() && !run.samples.empty()) {
      write_trajectory_plots(options->plot, scene, model, p, run, plane);
      std::cout << "  plots in " << options->plot << " (plots.md)\n";
    }
    if (run.failure) {
      std::cout.flush();
      std::cerr << "nhc: error: " << run.failure->what() << "\n";
      return kExitMathFailure;
    }
    return kExitOk;
  };
}

}  // namespace nhc::cli
