// nhc simulate SCENE [--model M] [--t-end T] [--rtol R] [--atol A] [--max-steps N] [--project]
//              [--repair-initial] [--set P=V]... [--outputs N | --output-times SPEC] [--stop-when EXPR]
//              [--columns NAMES] [--sensitivity NAMES] [-o FILE.csv | -o -] [--plot DIR [--plot-xy a,b]]
//
// The whole pipeline on one model: derive, reduce to index 1, generate the header
// (docs/generated-code.md), compile it with the C++ compiler found at configure time into a
// cached shared object, load it, integrate with nhc::runtime (IDA), write the CSV and print a
// summary. Numerical failures (the Appell–Hamel stop at t*, singular iteration matrices, NaN)
// end with a diagnostic naming t and exit code 3; the CSV then holds the solution up to there
// (and is not written when there is no row). Given initial values that miss a hidden constraint
// are reported before anything is compiled (initial_point.hpp's rule and words, as analyze).
#include <algorithm>
#include <cmath>
#include <iostream>

#include "simulate_command.hpp"

#include "commands.hpp"
#include "flag_rules.hpp"
#include "nhc/app/output_selection.hpp"
#include "nhc/app/scene_outputs.hpp"
#include "nhc/app/input_signals.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "progress_bar.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/app/preparation.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/app/run_engine.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/jit.hpp"
#include "nhc/jit/compile_behind.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/tolerances.hpp"
#include "nhc/base/clock.hpp"
#include "nhc/base/number_text.hpp"
#include "program_main.hpp"
#include "run_flags.hpp"
#include "trajectory_plots.hpp"
#include "sensitivity_option.hpp"

namespace nhc::cli {

namespace {

/// The run's drift lines: the reference error, the hidden (or, for suslov, monitored) constraints
/// and the invariants over the samples.
void write_drift_summary(std::ostream& info, const Scene& scene, const runtime::Model& model, ModelKind kind,
                         const runtime::DriftReport& drift, bool reference_applies) {
  if (model.n_reference() > 0 && reference_applies)
    info << "  max reference error " << base::number_text(drift.max_error, 3) << "\n";
  if (model.n_reference() > 0 && !reference_applies)  // docs/combinations.md
    info << "  no reference error: the closed forms of [reference] start from the scene's own [initial], and "
            "--initial moved the start\n";
  if (kind == ModelKind::suslov) {
    // Suslov's model monitors its constraints instead of enforcing them (models.md): their
    // values are the CSV's constraint:f<i> columns, zero at t0 (the start point of nhc analyze).
    for (int i = 0; i < model.n_hidden(); ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      info << "  monitored constraint " << model.hidden_name(i)
           << (k < scene.constraint_texts.size() ? " = " + scene.constraint_texts[k] : std::string()) << " (CSV column "
           << runtime::hidden_column(model, i) << "): value at t0 "
           << base::number_text(drift.first_hidden_each.at(k), 3) << ", max |" << model.hidden_name(i) << "| "
           << base::number_text(drift.max_hidden_each[k], 3) << " (not enforced by the suslov model)\n";
    }
  } else if (model.n_hidden() > 0) {
    info << "  max hidden-constraint drift " << base::number_text(drift.max_hidden, 3) << "\n";
  }
  // "change", not "drift": an invariant is a quantity the run watches, and whether the scene's
  // physics conserves it (a driven turntable pumps energy into a ball) is not the summary's to
  // say; where it is conserved, its change is the integration's drift (docs/scenes.md).
  for (int k = 0; k < model.n_invariants(); ++k)
    info << "  invariant " << model.table().invariant_names[k] << ": max change "
         << base::number_text(drift.invariant_drift[k], 3)
         << (drift.invariant_absolute[k]
                 ? " (absolute: the invariant stays below " + base::number_text(runtime::kInvariantScaleFloor, 3) + ")"
                 : " (relative " + base::number_text(drift.invariant_relative[k], 3) + " to its largest size " +
                       base::number_text(drift.invariant_scale[k], 3) + ")")
         << "\n";
}

}  // namespace

int run_simulate(SimulateOptions& options) {
  // Derive, reduce, generate (Jacobian kind by nhc::default_jacobian_kind), compile (or reuse), load.
  const auto load_start = base::Clock::now();
  const Scene scene = load_run_scene(options.run);
  const ModelKind kind = model_or_default(scene, options.run.model);
  app::require_model_inputs(scene, kind);
  const std::vector<app::ParameterOverride> overrides = app::parse_parameter_overrides(scene, options.run.set);
  Scene scene_set = scene;  // the overridden values for the analysis; the model takes them at run time
  app::apply_parameter_overrides(scene_set, overrides);
  check_run_flags(options.run, scene_set, kind);  // before anything is compiled or written
  // The scene's [controller]: the run goes from sample to sample (app/run_engine.hpp).
  const bool sampled = scene.controller.present;
  const bool variational = variational_integrator(options.run);
  check_run_features(options.run, scene, !options.sensitivity.names.empty());  // the engine's refusals
  // Model predictive control solves with IPOPT, which only nhc-optimize loads (command_programs.hpp).
  if (scene.controller.mpc.present && !mpc_factory) {
    static const CommandProgram with_ipopt{"simulate", "nhc-optimize", ""};
    return start_command_program(with_ipopt, program_arguments());
  }
  const bool csv_to_stdout = options.output == "-";
  const std::vector<SceneEvent> scene_events = run_events(options.run, scene);
  // The event table beside the CSV (docs/scenes.md, [events]).
  std::string side_note;  // -o a device or FIFO: no file beside it (the output policy, nhc/io/output_path.hpp)
  const std::string events_path = !scene_events.empty() || app::sliding_contact(scene)
                                      ? app::side_file_path(options.output, app::events_csv_path, side_note)
                                      : std::string();
  const bool write_event_table = !events_path.empty();
  // Every file the run reads: the scene and the --input series (nhc/io/output_path.hpp).
  std::vector<std::string> inputs = app::input_files(options.run.inputs);
  inputs.insert(inputs.begin(), options.run.scene_path);
  if (!options.output.empty() && !csv_to_stdout) check_output_file(options.output, inputs);
  if (write_event_table) check_output_file(events_path, inputs);
  if (!options.plot.empty()) check_output_directory(options.plot, inputs);
  std::ostream& info = csv_to_stdout ? std::cerr : std::cout;
  PathPlane plane;
  if (!options.plot.empty()) require_gnuplot("--plot"), plane = path_plane(scene, options.plot_xy, "--plot-xy");
  // The run's numbers from scene_set: a contact's mu, the period, t0 and [simulate] written through
  // parameters follow --set (app::set_parameter_values).
  const double t0 = scene_set.initial.t0;
  const std::vector<double> times = run_times(options.run, scene_set);
  const double t_end = times.back();
  const auto inputs_start = base::Clock::now();
  const app::InputSignals input_signals = app::parse_input_signals(scene_set, options.run.inputs, t0, t_end);
  const double input_seconds = base::seconds_since(inputs_start);  // reading --input files is not deriving
  // Derived and analysed once (app::prepare_and_build, as Python's Scene.build): the initial-point
  // check's analysis is what the build reduces.
  Scene scene_checked = scene_set;
  scene_checked.simulate.rtol = options.run.rtol.value_or(scene_set.simulate.rtol);
  scene_checked.simulate.atol = options.run.atol.value_or(scene_set.simulate.atol);
  app::Preparation preparation(std::move(scene_checked), kind);
  jit::BuildOptions build_options;
  build_options.sensitivities = !options.sensitivity.names.empty();
  build_options.variational = variational;
  build_options.backend = run_backend(options.run);
  const double before_check_seconds = base::seconds_since(load_start) - input_seconds;
  const app::PreparedModel prepared = app::prepare_and_build(preparation, scene, options.run.repair, build_options);
  const app::InitialPointCheck& check = prepared.check;
  const double load_seconds = before_check_seconds + prepared.check_seconds;
  const jit::LoadedModel& built = prepared.built;
  // What --sensitivity differentiates by, a parameter only [initial] is written through among them.
  const std::vector<runtime::SensitivityParameter> thetas =
      build_options.sensitivities
          ? app::sensitivity_parameters(scene_set, built.model(), options.sensitivity.names, "--sensitivity")
          : std::vector<runtime::SensitivityParameter>{};
  const runtime::Model& model = built.model();
  const double derive_seconds =
      load_seconds + built.timings().derive + built.timings().generate + built.timings().scene_cache;
  const bool scene_cached = check.cached && built.timings().scene_cached;
  const double compile_seconds = built.timings().compile + built.timings().load;

  // Integrate.
  runtime::IntegratorOptions io = run_integrator_options(options.run, scene_set);
  io.progress = terminal_progress();
  // --backend auto: a long interpreted run compiles its model behind it (compile_behind.hpp).
  jit::CompileBehind behind(scene, kind, build_options, built);
  if (built.timings().interpreted)
    io.progress = [&behind, bar = io.progress](const runtime::Progress& at) {
      behind.poll();
      if (bar) bar(at);
    };
  const std::vector<double> p = app::parameters_with_overrides(model, overrides);
  app::SceneOutputs outputs(scene_set, model, p);  // [outputs] and [contacts]: extra CSV columns
  for (const std::string& note : outputs.notes()) std::cerr << note << "\n";
  // The controller's laws against the model, before the run; its states are CSV columns.
  std::shared_ptr<app::ControllerLaws> controller;
  app::ExtraColumns controller_columns;
  std::optional<MpcParts> mpc;
  if (sampled && scene.controller.mpc.present) {
    mpc = mpc_factory(scene_set, model, times);
    controller_columns.names = mpc->columns;
  } else if (sampled) {
    controller = std::make_shared<app::ControllerLaws>(scene_set, model, p);
    controller_columns.names = controller->state_columns();
  }
  const app::ExtraColumns* extra = sampled ? &controller_columns : nullptr;
  const std::vector<std::string> columns =
      options.columns.empty() ? std::vector<std::string>{}
                              : app::parse_columns(options.columns, app::csv_columns(model, p, outputs, extra));
  const runtime::InitialState initial = run_initial_state(options.run, scene_set, model);
  if (build_options.sensitivities) check_sensitivities_given(thetas, initial);
  // The run: app::simulate, the one engine of every front end (app/run_engine.hpp).
  std::optional<jit::LoadedModel> sliding;
  app::RunPlan plan = run_plan(options.run, scene_set, kind, build_options, model, p, times, io,
                               input_function(input_signals, model, p), controller, sliding);
  if (mpc) plan.control = mpc->control;
  app::RunOutcome outcome = app::simulate(plan);
  if (sampled)
    controller_columns.rows = outcome.controller_rows, controller_columns.rows.resize(outcome.run.samples.size());
  if (outcome.slide && !outcome.sliding.empty()) {
    std::vector<std::pair<double, double>> spans;
    for (const app::SlidingSpan& s : outcome.sliding) spans.emplace_back(s.from, s.to);
    outputs.contacts().set_sliding(outcome.slide->name, spans, outcome.sliding[0].from_included);
  }
  const runtime::RunResult& run = outcome.run;
  std::optional<runtime::SensitivityRun> sensitivities;  // --sensitivity: the CSV comes from this run
  if (build_options.sensitivities) {
    runtime::SensitivityOptions so;
    so.error_control = options.sensitivity.error_control == "on";
    sensitivities = app::simulate_sensitivities(plan, thetas, so);
  }
  auto write_rows = [&](std::ostream& out) {
    if (sensitivities) runtime::write_sensitivity_csv(out, model, p, thetas, sensitivities->samples);
    else app::write_selected_csv(out, model, p, run.samples, columns, outputs, extra);
  };
  // No row, no file: a header-only CSV would look like a result.
  const std::size_t csv_rows = sensitivities ? sensitivities->samples.size() : run.samples.size();
  const bool csv_cut_short = sensitivities ? sensitivities->failure.has_value() : run.failure.has_value();
  const bool write_csv = !options.output.empty() && csv_rows > 0;
  if (write_csv && csv_to_stdout) {
    write_rows(std::cout);
    std::cout.flush();
  } else if (write_csv) {
    write_file_atomically(options.output, write_rows);
  }

  const bool switched = behind.switched();
  const bool compiled_behind = behind.finish();

  // Summary.
  const runtime::Statistics& st = run.statistics;
  // A contact that slid: the rolling model's hidden constraints and invariants hold while it
  // rolls; the drift is measured over those samples (app::RunOutcome::drift_samples).
  const runtime::DriftReport drift = runtime::measure_drift(model, p, outcome.drift_samples);
  const bool started = !run.samples.empty();
  info << "nhc simulate: " << scene.name << ", model " << to_string(kind);
  if (started) info << ", t from " << t0 << " to " << run.samples.back().t << " (of " << t_end << ")";
  else info << ", never started: the run stopped at t0 = " << t0 << " (t_end " << t_end << ")";
  if (variational)
    info << ", variational integrator (discrete Lagrange-d'Alembert, midpoint), step " << *options.run.step
         << "\n  steps " << st.steps << ", Newton iterations " << st.nonlinear_iterations << ", residual evaluations "
         << st.residual_evaluations << ", Jacobian evaluations " << st.jacobian_evaluations << " (" << st.linear_solver
         << ", " << st.jacobian << ")";
  else
    info << ", rtol " << io.rtol << ", atol " << io.atol << (options.run.project ? ", projection" : "") << "\n"
         << "  steps " << st.steps << ", residual evaluations " << st.residual_evaluations << ", Jacobian evaluations "
         << st.jacobian_evaluations << " (" << st.linear_solver << ", " << st.jacobian << "), error-test failures "
         << st.error_test_failures << ", nonlinear failures " << st.nonlinear_failures;
  if (options.run.project) info << ", projections " << st.projections;
  info << "\n  time: derive " << base::number_text(derive_seconds, 3) << " s" << (scene_cached ? " (scene cache)" : "")
       << (built.timings().interpreted ? (switched          ? ", interpreted, then compiled behind the run"
                                          : compiled_behind ? ", interpreted (compiled behind it for the next run)"
                                                            : ", interpreted (no compile)")
                                       : ", compile " + base::number_text(compile_seconds, 3) + " s" +
                                             (built.library().reused ? " (cached)" : ""))
       << ", integrate " << base::number_text(st.initialization_seconds + st.integration_seconds, 3) << " s";
  if (!app::input_files(options.run.inputs).empty())
    info << ", read inputs " << base::number_text(input_seconds, 3) << " s";
  info << "\n";
  if (sensitivities) info << describe_sensitivity_cost(*sensitivities, options.sensitivity, st);
  // Errors and drifts of a run without a sample would read as zeros: there are none to report.
  if (started) write_drift_summary(info, scene, model, kind, drift, options.run.initial.empty());
  if (started && outcome.max_discrete_constraint)
    info << "  max discrete-constraint residual " << base::number_text(*outcome.max_discrete_constraint, 3)
         << " (the constraints the steps solve; the hidden constraints above are evaluated at the\n"
            "  node velocities (q_{k+1} - q_{k-1})/2h and their interpolants, O(h^2): docs/variational.md)\n";

  for (const std::string& line : outputs.contacts().need_lines(run.samples)) info << "  " << line << "\n";
  for (const std::string& line : outcome.notes) info << "  " << line << "\n";
  for (const runtime::EventHit& hit : run.events) {  // a contact's slip in words (contact_forces.hpp)
    const std::optional<std::string> slip = outputs.contacts().slip_line(hit);
    info << "  " << (slip ? *slip : app::event_line(hit)) << "\n";
  }
  if (!side_note.empty()) info << "  " << side_note << "\n";
  if (write_event_table && started) {
    write_file_atomically(events_path, [&](std::ostream& out) { app::write_events_csv(out, run.events); });
    info << "  wrote " << events_path << " (" << run.events.size() << " event" << (run.events.size() == 1 ? "" : "s")
         << ")\n";
  }
  if (sampled)
    info << "  sampled controller: period " << scene_set.controller.period << ", " << run.samples.size()
         << " samples at t0 + k*period, inputs held between them\n";
  if (mpc) info << "  " << mpc->summary() << "\n";
  if (!outputs.empty()) {
    info << "  outputs (CSV columns, not checked for drift):";
    for (const std::string& name : outputs.names()) info << " " << name;
    info << "\n";
  }
  if (write_csv)
    info << "  wrote " << (csv_to_stdout ? std::string("the CSV to standard output") : options.output) << " ("
         << csv_rows << " rows" << (csv_cut_short ? ", the motion up to the failure" : "") << ")\n";
  else if (!options.output.empty())
    info << "  no CSV written: the run" << (sensitivities ? " with sensitivities" : "") << " did not get past t0\n";
  else info << "  no CSV written (-o FILE.csv, or -o - for standard output)\n";
  if (!options.plot.empty() && run.samples.empty()) info << "  no plots: the run did not get past t0\n";
  if (!options.plot.empty() && !run.samples.empty()) {
    write_trajectory_plots(options.plot, scene, model, p, run, plane, inputs);
    info << "  plots in " << options.plot << " (plots.md)\n";
  }
  if (sensitivities && sensitivities->failure && !run.failure) {  // the plain run's plots are drawn
    info.flush();
    std::cerr << "nhc: error: sensitivities: " << sensitivities->failure->what() << "\n";
    return kExitMathFailure;
  }
  if (run.failure) {
    info.flush();
    // A run that fails before its first step at a point the analysis found singular: the
    // analysis' words say why (nhc analyze prints the same), not the solver's symptom.
    if (!started && !check.problems_at_t0.empty()) {
      for (const std::string& problem : check.problems_at_t0) std::cerr << "nhc: error: " << problem << "\n";
      return kExitMathFailure;
    }
    std::cerr << "nhc: error: " << run.failure->what() << "\n";
    return kExitMathFailure;
  }
  return kExitOk;
}

CommandRunner add_simulate_command(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* sub =
      app.add_subcommand("simulate", "derive, generate, compile and integrate one model of a scene with SUNDIALS IDA");
  add_run_flags(sub, options->run);
  sub->add_option("--columns", options->columns, "x,y,...: the CSV columns after t (default: all)");
  sub->add_option("-o,--output", options->output,
                  "CSV file for the solution ('-': standard output, the summary then on standard error)");
  CLI::Option* plot = sub->add_option("--plot", options->plot,
                                      "directory for plots (SVG, PNG) of the coordinates, path, multipliers and drift");
  sub->add_option("--plot-xy", options->plot_xy, "a,b: the plane of the path plot (default: the first two coordinates)")
      ->needs(plot);
  add_sensitivity_options(sub, options->sensitivity);

  return [options]() { return run_simulate(*options); };
}

}  // namespace nhc::cli
