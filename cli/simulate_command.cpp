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
#include "nhc/app/law_input_values.hpp"
#include "nhc/app/scene_outputs.hpp"
#include "nhc/app/input_signals.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "progress_bar.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/app/preparation.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/app/switched_run.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/jit.hpp"
#include "nhc/jit/compile_behind.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/tolerances.hpp"
#include "nhc/clock.hpp"
#include "nhc/runtime/number_text.hpp"
#include "run_flags.hpp"
#include "trajectory_plots.hpp"
#include "sensitivity_option.hpp"

namespace nhc::cli {

namespace {

std::string format(double v, int precision = 3) { return runtime::number_text(v, precision); }

/// The run's drift lines: the reference error, the hidden (or, for suslov, monitored) constraints
/// and the invariants over the samples.
void write_drift_summary(std::ostream& info, const Scene& scene, const runtime::Model& model, ModelKind kind,
                         const runtime::DriftReport& drift) {
  if (model.n_reference() > 0) info << "  max reference error " << format(drift.max_error) << "\n";
  if (kind == ModelKind::suslov) {
    // Suslov's model monitors its constraints instead of enforcing them (models.md): their
    // values are the CSV's constraint:f<i> columns, zero at t0 (the start point of nhc analyze).
    for (int i = 0; i < model.n_hidden(); ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      info << "  monitored constraint " << model.hidden_name(i)
           << (k < scene.constraint_texts.size() ? " = " + scene.constraint_texts[k] : std::string()) << " (CSV column "
           << runtime::hidden_column(model, i) << "): value at t0 " << format(drift.first_hidden_each.at(k))
           << ", max |" << model.hidden_name(i) << "| " << format(drift.max_hidden_each[k])
           << " (not enforced by the suslov model)\n";
    }
  } else if (model.n_hidden() > 0) {
    info << "  max hidden-constraint drift " << format(drift.max_hidden) << "\n";
  }
  for (int k = 0; k < model.n_invariants(); ++k)
    info << "  invariant " << model.table().invariant_names[k] << ": max drift "
              << format(drift.invariant_drift[k])
              << (drift.invariant_absolute[k]
                      ? " (absolute: the invariant stays below " + format(runtime::kInvariantScaleFloor) + ")"
                      : " (relative " + format(drift.invariant_relative[k]) + " to its largest size " +
                            format(drift.invariant_scale[k]) + ")")
              << "\n";
}

}  // namespace

int run_simulate(SimulateOptions& options) {
  // Derive, reduce, generate (Jacobian kind by nhc::default_jacobian_kind), compile (or reuse), load.
  const auto load_start = Clock::now();
  const Scene scene = load_run_scene(options.run);
  const ModelKind kind = model_or_default(scene, options.run.model);
  app::require_model_inputs(scene, kind);
  // Sensitivities follow the inputs' default signals, whose dependence on the parameters the
  // generated dF/dp includes; an --input replacing one has none (docs/runtime.md, "Sensitivities").
  if (!options.sensitivity.names.empty() && !options.run.inputs.empty())
    throw InputError({"--input", 0, 0}, "--sensitivity follows the scene's default input signals: it does not go with "
                                        "--input (the derivative of a replaced input by the parameters is not known)");
  check_run_flags(options.run, scene, kind);  // before anything is compiled or written
  // The scene's [controller]: the run goes from sample to sample (app/sampled_run.hpp).
  const bool sampled = scene.controller.present;
  if (sampled) {
    if (!options.sensitivity.names.empty())
      throw InputError({"--sensitivity", 0, 0}, "--sensitivity: the scene's [controller] (" +
                                                    scene.controller.where.str() + ") is not differentiated");
    for (const std::string& assignment : options.run.inputs) {
      const std::string name = assignment.substr(0, assignment.find('='));
      for (const SceneControllerLaw& law : scene.controller.inputs)
        if (law.name == name)
          throw InputError({"--input", 0, 0}, "--input " + name + ": the scene's [controller] sets it (" +
                                                  law.where.str() + ")");
    }
    if (app::sliding_contact(scene))
      throw InputError(scene.controller.where, "a [controller] and a contact that slides (on_slip = \"slide\") do not "
                                               "go together yet: the sampled run integrates one model");
  }
  const bool variational = variational_integrator(options.run);
  if (variational && !options.sensitivity.names.empty())
    throw InputError({options.run.scene_path, 0, 0},
                     "--sensitivity integrates with IDAS; it does not go with --integrator variational");
  const bool csv_to_stdout = options.output == "-";
  const std::vector<SceneEvent> scene_events = run_events(options.run, scene);
  // The event table beside the CSV (docs/scenes.md, [events]).
  const bool write_event_table = (!scene_events.empty() || app::sliding_contact(scene)) && !options.output.empty() &&
                                 !csv_to_stdout;
  const std::string events_path = write_event_table ? app::events_csv_path(options.output) : std::string();
  // Every file the run reads: the scene and the --input series (nhc/io/output_path.hpp).
  std::vector<std::string> inputs = app::input_files(options.run.inputs);
  inputs.insert(inputs.begin(), options.run.scene_path);
  if (!options.output.empty() && !csv_to_stdout) check_output_file(options.output, inputs);
  if (write_event_table) check_output_file(events_path, inputs);
  if (!options.plot.empty()) check_output_directory(options.plot, inputs);
  std::ostream& info = csv_to_stdout ? std::cerr : std::cout;
  PathPlane plane;
  if (!options.plot.empty()) require_gnuplot("--plot"), plane = path_plane(scene, options.plot_xy, "--plot-xy");
  const std::vector<app::ParameterOverride> overrides = app::parse_parameter_overrides(scene, options.run.set);
  Scene scene_set = scene;  // the overridden values for the analysis; the model takes them at run time
  app::apply_parameter_overrides(scene_set, overrides);
  const double t0 = scene.initial.t0;
  const std::vector<double> times =
      sampled ? app::scene_controller_samples(run_request(options.run, scene), scene, app::command_line_names())
              : run_output_times(options.run, scene);
  const double t_end = times.back();
  const auto inputs_start = Clock::now();
  const app::InputSignals input_signals = app::parse_input_signals(scene_set, options.run.inputs, t0, t_end);
  const double input_seconds = seconds_since(inputs_start);  // reading --input files is not deriving
  // Derived and analysed once (app::prepare_and_build, as Python's Scene.build): the initial-point
  // check's analysis is what the build reduces.
  Scene scene_checked = scene_set;
  scene_checked.simulate.rtol = options.run.rtol.value_or(scene.simulate.rtol);
  scene_checked.simulate.atol = options.run.atol.value_or(scene.simulate.atol);
  app::Preparation preparation(std::move(scene_checked), kind);
  jit::BuildOptions build_options;
  build_options.sensitivities = !options.sensitivity.names.empty();
  build_options.variational = variational;
  build_options.backend = run_backend(options.run);
  const double before_check_seconds = seconds_since(load_start) - input_seconds;
  const app::PreparedModel prepared = app::prepare_and_build(preparation, scene, options.run.repair, build_options);
  const app::InitialPointCheck& check = prepared.check;
  const double load_seconds = before_check_seconds + prepared.check_seconds;
  const jit::LoadedModel& built = prepared.built;
  for (const std::string& name : options.sensitivity.names)
    app::refuse_unread_parameter(scene, built.model(), name, "--sensitivity", "its sensitivities are all zero");
  if (build_options.sensitivities) parse_sensitivities(built.model(), options.sensitivity.names);
  const runtime::Model& model = built.model();
  const double derive_seconds =
      load_seconds + built.timings().derive + built.timings().generate + built.timings().scene_cache;
  const bool scene_cached = check.cached && built.timings().scene_cached;
  const double compile_seconds = built.timings().compile + built.timings().load;

  // Integrate.
  runtime::IntegratorOptions io = run_integrator_options(options.run, scene);
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
  if (sampled) {
    controller = std::make_shared<app::ControllerLaws>(scene_set, model, p);
    controller_columns.names = controller->state_columns();
  }
  const app::ExtraColumns* extra = sampled ? &controller_columns : nullptr;
  const std::vector<std::string> columns =
      options.columns.empty() ? std::vector<std::string>{}
                              : app::parse_columns(options.columns, app::csv_columns(model, p, outputs, extra));
  const runtime::InitialState initial = run_initial_state(options.run, scene_set, model);
  if (build_options.sensitivities) check_sensitivities_given(model, initial, options.sensitivity.names);
  // Events are located by IDA in the plain run; the sensitivities' run and the variational
  // integrator locate none (--stop-when is refused with the latter, app::run_events).
  const std::vector<runtime::Event> events = app::runtime_events(scene_events, scene_set, model, p);
  if (!events.empty() && (variational || build_options.sensitivities))
    std::cerr << "note: the scene's [events] are located by IDA in a plain run only: "
              << (variational ? "the variational integrator" : "the run with sensitivities") << " ignores them\n";
  // A contact with on_slip = "slide": the run switches between the rolling and the sliding model
  // (app/switched_run.hpp); in the plain IDA run only, like the events.
  const SceneContact* slide = variational || build_options.sensitivities ? nullptr : app::sliding_contact(scene_set);
  if (!slide && app::sliding_contact(scene_set))
    std::cerr << "note: contact '" << app::sliding_contact(scene_set)->name << "' slides (on_slip = \"slide\") in a plain IDA run only: "
              << (variational ? "the variational integrator" : "the run with sensitivities") << " integrates the rolling model\n";
  FlaggedRun flagged;
  std::vector<std::string> switch_notes;
  std::vector<app::SlidingSpan> sliding_spans;
  if (sampled) {
    io.progress = nullptr;  // one integration per sample: a bar would restart at every one
    app::SampledRun s = app::simulate_sampled(model, p, initial, times, io, app::sample_law(controller),
                                              controller->held(), app::input_function(input_signals, model, p));
    flagged.run = std::move(s.run);
    controller_columns.rows = controller->state_history();
    controller_columns.rows.resize(flagged.run.samples.size());
  } else if (slide) {
    const jit::LoadedModel sliding = app::build_sliding_model(scene_set, *slide, kind, build_options);
    app::SwitchedRun switched = app::simulate_switched(scene_set, *slide, model, sliding.model(), p, initial, times, io,
                                                       scene_events, app::input_function(input_signals, model, p));
    flagged.run = std::move(switched.run);
    switch_notes = std::move(switched.notes);
    sliding_spans = switched.sliding;
    std::vector<std::pair<double, double>> spans;
    for (const app::SlidingSpan& s : switched.sliding) spans.emplace_back(s.from, s.to);
    outputs.contacts().set_sliding(slide->name, spans, !switched.sliding.empty() && switched.sliding[0].from_included);
  } else {
    flagged = run_with_flags(options.run, model, p, initial, times, io, app::input_function(input_signals, model, p), events);
  }
  app::record_law_inputs(scene_set, model, p, flagged.run.samples);  // the laws' input:NAME columns
  const runtime::RunResult& run = flagged.run;
  std::optional<runtime::SensitivityRun> sensitivities;  // --sensitivity: the CSV comes from this run
  if (build_options.sensitivities)
    sensitivities = run_sensitivities(model, p, initial, times, io, options.sensitivity);
  if (sensitivities) app::record_law_inputs(scene_set, model, p, sensitivities->samples);
  auto write_rows = [&](std::ostream& out) {
    if (sensitivities)
      runtime::write_sensitivity_csv(out, model, p, parse_sensitivities(model, options.sensitivity.names),
                                     sensitivities->samples);
    else
      app::write_selected_csv(out, model, p, run.samples, columns, outputs, extra);
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
  // rolls; the drift is measured over those samples.
  std::vector<runtime::Sample> rolling_samples;
  if (!sliding_spans.empty()) {
    rolling_samples = app::rolling_samples(run.samples, sliding_spans);
    switch_notes.push_back("the drift above is measured over the samples where contact " + slide->name +
                           " rolls (" + std::to_string(rolling_samples.size()) + " of " +
                           std::to_string(run.samples.size()) + ")");
  }
  const runtime::DriftReport drift =
      runtime::measure_drift(model, p, sliding_spans.empty() ? run.samples : rolling_samples);
  const bool started = !run.samples.empty();
  info << "nhc simulate: " << scene.name << ", model " << to_string(kind);
  if (started)
    info << ", t from " << t0 << " to " << run.samples.back().t << " (of " << t_end << ")";
  else
    info << ", never started: the run stopped at t0 = " << t0 << " (t_end " << t_end << ")";
  if (variational)
    info << ", variational integrator (discrete Lagrange-d'Alembert, midpoint), step " << *options.run.step
         << "\n  steps " << st.steps << ", Newton iterations " << st.nonlinear_iterations
         << ", residual evaluations " << st.residual_evaluations << ", Jacobian evaluations "
         << st.jacobian_evaluations << " (" << st.linear_solver << ", " << st.jacobian << ")";
  else
    info << ", rtol " << io.rtol << ", atol " << io.atol << (options.run.project ? ", projection" : "") << "\n"
         << "  steps " << st.steps << ", residual evaluations " << st.residual_evaluations
         << ", Jacobian evaluations " << st.jacobian_evaluations << " (" << st.linear_solver << ", "
         << st.jacobian << "), error-test failures " << st.error_test_failures << ", nonlinear failures "
         << st.nonlinear_failures;
  if (options.run.project) info << ", projections " << st.projections;
  info << "\n  time: derive " << format(derive_seconds) << " s" << (scene_cached ? " (scene cache)" : "")
       << (built.timings().interpreted
               ? (switched          ? ", interpreted, then compiled behind the run"
                  : compiled_behind ? ", interpreted (compiled behind it for the next run)"
                                    : ", interpreted (no compile)")
                                       : ", compile " + format(compile_seconds) + " s" +
                                             (built.library().reused ? " (cached)" : ""))
       << ", integrate "
            << format(st.initialization_seconds + st.integration_seconds) << " s";
  if (!app::input_files(options.run.inputs).empty()) info << ", read inputs " << format(input_seconds) << " s";
  info << "\n";
  if (sensitivities) info << describe_sensitivity_cost(*sensitivities, options.sensitivity, st);
  // Errors and drifts of a run without a sample would read as zeros: there are none to report.
  if (started) write_drift_summary(info, scene, model, kind, drift);
  if (started && flagged.max_discrete_constraint)
    info << "  max discrete-constraint residual " << format(*flagged.max_discrete_constraint)
         << " (the constraints the steps solve; the hidden constraints above are evaluated at the\n"
            "  node velocities (q_{k+1} - q_{k-1})/2h and their interpolants, O(h^2): docs/variational.md)\n";

  for (const std::string& line : outputs.contacts().need_lines(run.samples)) info << "  " << line << "\n";
  for (const std::string& line : switch_notes) info << "  " << line << "\n";
  for (const runtime::EventHit& hit : run.events) {  // a contact's slip in words (contact_forces.hpp)
    const std::optional<std::string> slip = outputs.contacts().slip_line(hit);
    info << "  " << (slip ? *slip : app::event_line(hit)) << "\n";
  }
  if (write_event_table && started) {
    write_file_atomically(events_path, [&](std::ostream& out) { app::write_events_csv(out, run.events); });
    info << "  wrote " << events_path << " (" << run.events.size() << " event" << (run.events.size() == 1 ? "" : "s")
         << ")\n";
  }
  if (sampled)
    info << "  sampled controller: period " << scene.controller.period << ", " << run.samples.size()
         << " samples at t0 + k*period, inputs held between them\n";
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
  else
    info << "  no CSV written (-o FILE.csv, or -o - for standard output)\n";
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
  CLI::App* sub = app.add_subcommand(
      "simulate", "derive, generate, compile and integrate one model of a scene with SUNDIALS IDA");
  add_run_flags(sub, options->run);
  sub->add_option("--columns", options->columns, "x,y,...: the CSV columns after t (default: all)");
  sub->add_option("-o,--output", options->output,
                  "CSV file for the solution ('-': standard output, the summary then on standard error)");
  CLI::Option* plot = sub->add_option(
      "--plot", options->plot, "directory for plots (SVG, PNG) of the coordinates, path, multipliers and drift");
  sub->add_option("--plot-xy", options->plot_xy, "a,b: the plane of the path plot (default: the first two coordinates)")
      ->needs(plot);
  add_sensitivity_options(sub, options->sensitivity);

  return [options]() { return run_simulate(*options); };
}

}  // namespace nhc::cli
