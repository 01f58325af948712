// nhc animate SCENE [--model M] [the run flags of nhc simulate] [--path FILE.csv] -o DIR
//
// Runs one model as `nhc simulate` does (or reads its motion from --path, e.g. nhc optimize's
// CSV, whose columns name the model's states) and writes DIR/index.html: the scene's [visual] shapes
// moving along the run, a self-contained page with three.js beside it (docs/animate.md). A run
// that fails part way still gets its page (the motion up to the failure) and exits 3.
#include <iostream>

#include <fmt/format.h>

#include "nhc/app/preparation.hpp"
#include "nhc/app/run_engine.hpp"
#include "animation_page.hpp"
#include "commands.hpp"
#include "nhc/app/input_signals.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/errors.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "progress_bar.hpp"
#include "nhc/app/scene_events.hpp"
#include "plots.hpp"
#include "run_flags.hpp"
#include "visual_samples.hpp"

namespace nhc::cli {

namespace {

struct AnimateOptions {
  RunFlags run;
  std::string output;
  std::string path;  ///< --path FILE.csv: draw this motion instead of running
};

/// The samples of a motion written as CSV (nhc optimize's): column t, a column per state of the
/// model by its name (required but for the algebraic ones, 0 when absent), its rate's where
/// present (name'), each input's. InputError at --path.
std::vector<runtime::Sample> samples_from_file(const runtime::Model& model, const std::string& path) {
  CsvTable table;
  try {
    table = read_csv_table(path, /*finite_only=*/true);
  } catch (const InputError&) {
    throw;  // at its file, line and column
  } catch (const std::exception& e) {
    throw InputError({"--path", 0, 0}, path + ": " + e.what());
  }
  const int t = table.column("t");
  if (t < 0 || table.rows.empty()) throw InputError({"--path", 0, 0}, path + " has no column t or no rows");
  std::vector<int> y, yp, u;
  for (int k = 0; k < model.n_states(); ++k) {
    y.push_back(table.column(model.state_name(k)));
    yp.push_back(table.column(model.state_name(k) + "'"));
    if (y.back() < 0 && model.state_name(k).rfind("lambda", 0) != 0)
      throw InputError({"--path", 0, 0}, path + " has no column " + model.state_name(k) + " (a state of the model)");
  }
  for (int k = 0; k < model.n_inputs(); ++k) {
    const int c = table.column(model.input_name(k));
    u.push_back(c >= 0 ? c : table.column("input:" + model.input_name(k)));  // nhc simulate's name
  }
  std::vector<runtime::Sample> samples;
  auto cell = [](const std::vector<double>& row, int c) { return c < 0 ? 0.0 : row[static_cast<std::size_t>(c)]; };
  for (const std::vector<double>& row : table.rows) {
    runtime::Sample s;
    s.t = row[static_cast<std::size_t>(t)];
    if (!samples.empty() && !(s.t > samples.back().t))
      throw InputError({"--path", 0, 0}, path + ": t does not increase at t = " + fmt::format("{}", s.t));
    for (std::size_t k = 0; k < y.size(); ++k) {
      s.y.push_back(cell(row, y[k]));
      s.yp.push_back(cell(row, yp[k]));
    }
    for (int c : u) s.u.push_back(cell(row, c));
    samples.push_back(std::move(s));
  }
  return samples;
}

}  // namespace

CommandRunner add_animate_command(CLI::App& app) {
  auto options = std::make_shared<AnimateOptions>();
  CLI::App* sub = app.add_subcommand(
      "animate", "run one model of a scene and write a 3-D view of its [visual] shapes: DIR/index.html for a browser");
  add_run_flags(sub, options->run);
  sub->add_option("-o,--output", options->output, "directory for the page (index.html with three.js beside it)")
      ->required();
  sub->add_option(
      "--path", options->path,
      "draw the motion in this CSV (t and the model's states by name, e.g. nhc optimize's -o) instead of running");

  return [options]() {
    const Scene scene = load_run_scene(options->run);
    const RunFlags& flags = options->run;
    if (scene.visuals.empty())
      throw InputError(scene.file_location(), "the scene has no [visual] table: nothing to draw (shapes: " +
                                                  visual_shape_names() + "; docs/animate.md)");
    const ModelKind kind = model_or_default(scene, flags.model);
    app::require_model_inputs(scene, kind);
    const std::vector<app::ParameterOverride> overrides = app::parse_parameter_overrides(scene, flags.set);
    Scene scene_set = scene;  // the overridden values for the shapes; the model takes them at run time
    app::apply_parameter_overrides(scene_set, overrides);
    check_run_flags(flags, scene_set, kind);  // against the t0 and t_end the run takes (--set moves them)
    check_run_features(flags, scene, false);  // the engine's refusals, as nhc simulate's
    const std::vector<double> times = run_times(flags, scene_set);  // numbers written through parameters follow --set
    const app::InputSignals input_signals =
        app::parse_input_signals(scene_set, flags.inputs, scene_set.initial.t0, times.back());

    // The path of nhc simulate (app::prepare_and_build): given initial values that miss a hidden
    // constraint are refused in the analysis' words before anything is compiled.
    Scene scene_checked = scene_set;
    scene_checked.simulate.rtol = flags.rtol.value_or(scene_set.simulate.rtol);
    scene_checked.simulate.atol = flags.atol.value_or(scene_set.simulate.atol);
    app::Preparation preparation(std::move(scene_checked), kind);
    jit::BuildOptions build_options;
    build_options.variational = variational_integrator(flags);
    build_options.backend = run_backend(flags);
    const app::PreparedModel prepared = app::prepare_and_build(preparation, scene, flags.repair, build_options);
    const jit::LoadedModel& built = prepared.built;
    const runtime::Model& model = built.model();
    runtime::IntegratorOptions io = run_integrator_options(flags, scene_set);
    io.progress = terminal_progress();
    const std::vector<double> p = app::parameters_with_overrides(model, overrides);
    runtime::RunResult run;
    if (!options->path.empty()) {
      run.samples = samples_from_file(model, options->path);
    } else {  // the engine's run, as nhc simulate's: events, contacts, the controller
      std::shared_ptr<app::ControllerLaws> controller;
      if (scene.controller.present) controller = std::make_shared<app::ControllerLaws>(scene_set, model, p);
      std::optional<jit::LoadedModel> sliding;
      const app::RunPlan plan = run_plan(flags, scene_set, kind, build_options, model, p, times, io,
                                         app::input_function(input_signals, model, p), controller, sliding);
      run = app::simulate(plan).run;
    }
    if (run.samples.empty()) {
      std::cerr << "nhc: error: " << (run.failure ? run.failure->what() : "the run has no sample") << "\n"
                << "  no page written: the run did not get past t0\n";
      return kExitMathFailure;
    }
    AnimationContent content{scene.name, to_string(kind), {}, visual_tracks(scene_set, model, p, run.samples)};
    for (const runtime::Sample& s : run.samples) content.times.push_back(s.t);
    std::vector<std::string> inputs = app::input_files(flags.inputs);
    inputs.insert(inputs.begin(), flags.scene_path);
    if (!options->path.empty()) inputs.push_back(options->path);
    write_animation_page(options->output, content, inputs);

    std::cout << "nhc animate: " << scene.name << ", model " << to_string(kind) << ", t from "
              << fmt::format("{}", content.times.front()) << " to " << fmt::format("{}", content.times.back()) << ", "
              << content.times.size() << " samples, " << scene.visuals.size() << " shape"
              << (scene.visuals.size() == 1 ? "" : "s") << "\n  wrote " << options->output
              << "/index.html (open it in a browser; #t=1.5 opens it paused at t = 1.5)\n";
    if (run.failure) {
      std::cout.flush();
      std::cerr << "nhc: error: " << run.failure->what() << " (the page shows the motion up to there)\n";
      return kExitMathFailure;
    }
    return kExitOk;
  };
}

}  // namespace nhc::cli
