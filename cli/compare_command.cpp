// nhc compare SCENE [--models M,…] [--t-end T] [--rtol R] [--atol A] [--outputs N] [--tolerance TOL]
//                   [--initial NAME=VALUE]... [--plot-xy a,b] -o DIR
//
// The models of a scene side by side: each one derived, compiled and integrated from the same
// [initial] data (completed to its own consistent point), one CSV per model, overlaid plots of
// each coordinate, of the path and of the invariants, and DIR/compare.md (compare_report.hpp).
// Models that do not apply, or stop at t0, are listed with their reason. DIR appears whole or
// not at all (nhc/io/atomic_directory.hpp). Exit 3 when no model gets past t0.
#include <cmath>

#include "nhc/app/run_request.hpp"
#include "nhc/app/run_engine.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/base/primed_name.hpp"
#include <iostream>
#include <optional>
#include <regex>

#include "commands.hpp"
#include "flag_rules.hpp"
#include "compare_report.hpp"
#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/jit.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/app/initial_values.hpp"
#include "nhc/base/number_text.hpp"
#include "plots.hpp"
#include "run_flags.hpp"
#include "trajectory_plots.hpp"

namespace nhc::cli {

namespace {

struct CompareOptions {
  std::string scene_path;
  std::vector<std::string> models;
  std::optional<double> t_end, rtol, atol;
  int outputs = 200;
  double tolerance = 1e-6;
  std::vector<std::string> initial;  ///< --initial NAME=VALUE
  std::string plot_xy;
  std::string output;
};

/// The command with the flags that change the result (not -o), for compare.md.
std::string command_line(const CompareOptions& o) {
  std::string s = "nhc compare " + o.scene_path;
  if (!o.models.empty()) {
    s += " --models ";
    for (std::size_t k = 0; k < o.models.size(); ++k) s += (k ? "," : "") + o.models[k];
  }
  if (o.t_end) s += " --t-end " + base::number_text(*o.t_end, 15);
  if (o.rtol) s += " --rtol " + base::number_text(*o.rtol, 15);
  if (o.atol) s += " --atol " + base::number_text(*o.atol, 15);
  if (o.outputs != 200) s += " --outputs " + std::to_string(o.outputs);
  if (o.tolerance != 1e-6) s += " --tolerance " + base::number_text(o.tolerance, 15);
  for (const std::string& a : o.initial) s += " --initial " + a;
  if (!o.plot_xy.empty()) s += " --plot-xy " + o.plot_xy;
  return s;
}

/// The run settings with the flags applied, checked before anything is compiled or written.
CompareSettings settings_of(const CompareOptions& options, const Scene& scene) {
  CompareSettings s;
  s.command_line = command_line(options);
  s.scene_path = options.scene_path;
  s.scene_name = scene.name;
  s.coordinates = scene.jet->coordinates();
  s.given = scene.initial.values;
  s.t0 = scene.initial.t0;
  s.t_end = app::run_t_end(scene, options.t_end, "--t-end");  // the flag is checked finite
  s.rtol = options.rtol.value_or(scene.simulate.rtol);
  s.atol = options.atol.value_or(scene.simulate.atol);
  s.outputs = options.outputs;
  s.tolerance = options.tolerance;
  s.times = flag_rules::output_times(s.t0, s.t_end, s.outputs, "--t-end/--outputs");
  return s;
}

std::string outcome_of(const runtime::RunResult& run) {
  if (!run.failure) return "ran to the end";
  const base::SolverError& e = *run.failure;
  const bool singular = e.kind() == base::FailureKind::singular_constraint_gradient ||
                        e.kind() == base::FailureKind::singular_iteration_matrix;
  // The message's own "at t = <17 digits>" is left out: t is given once, to 6 digits.
  const std::string reason = std::regex_replace(e.what(), std::regex(" at t = [-+0-9.eE]+"), "");
  return std::string(singular ? "stopped at a singularity" : "stopped") + " at t = " + base::number_text(e.t(), 6) +
         ": " + reason;
}

/// The scene's constraints f^α along a motion, from the CSV columns (x, x', x'', …): every model
/// but suslov solves them, suslov's only monitors them (models.md).
std::vector<ConstraintCheck> check_constraints(const Scene& scene, const CsvTable& table) {
  const JetSpace& jet = *scene.jet;
  std::vector<ConstraintCheck> checks;
  for (int a = 0; a < scene.constraint_count(); ++a) {
    ConstraintCheck check{"f" + std::to_string(a + 1) + ": " + scene.constraint_texts[a], NAN, 0};
    std::size_t evaluated = 0;
    for (std::size_t row = 0; row < table.rows.size(); ++row) {
      GiNaC::exmap point = scene.parameter_substitution();
      point[jet.time()] = table.rows[row][table.column("t")];
      for (int i = 0; i < jet.coordinate_count(); ++i)
        for (int k = 0; k <= kMaxDerivativeOrder; ++k)
          if (const int c = table.column(base::primed_name(jet.coordinates()[i], static_cast<int>(k))); c >= 0)
            point[jet.q(i, k)] = table.rows[row][c];
      try {
        const double f = evaluate_real(scene.constraints[a], point, "constraint f" + std::to_string(a + 1));
        if (row == 0) check.at_t0 = f;
        check.largest = std::max(check.largest, std::abs(f));
        ++evaluated;
      } catch (const MathError&) {
        // Not finite at this point (a singular point), or a derivative the CSV does not hold.
      }
    }
    if (evaluated == 0) check.largest = NAN;
    checks.push_back(check);
  }
  return checks;
}

/// Builds and integrates one model into `dir/<model>.csv`; a model that does not apply, or
/// stops at t0, comes back with its reason and no CSV.
ComparedModel run_model(const Scene& scene, ModelKind kind, const CompareSettings& settings,
                        const std::filesystem::path& dir) {
  ComparedModel result;
  result.name = to_string(kind);
  std::optional<jit::LoadedModel> built;
  try {
    built.emplace(jit::build(scene, kind));
  } catch (const MathError& e) {
    result.unavailable = std::string("does not apply: ") + e.what();
    return result;
  }
  const runtime::Model& model = built->model();
  const jit::BuildTimings& bt = built->timings();
  result.build_seconds = bt.derive + bt.generate + bt.compile + bt.load;

  runtime::IntegratorOptions io;
  io.rtol = settings.rtol;
  io.atol = settings.atol;
  const std::vector<double> p = model.default_parameters();
  // The run engine's (app/run_engine.hpp) with the motions compared whole: no event ends one; a
  // contact that slides switches to its sliding model, as in nhc simulate.
  app::RunPlan plan;
  plan.scene = &scene;
  plan.model = &model;
  plan.p = p;
  plan.initial = app::initial_state_of(scene, model);
  plan.times = settings.times;
  plan.options = io;
  std::optional<jit::LoadedModel> sliding;
  if (const SceneContact* slide = app::sliding_contact(scene)) {
    sliding.emplace(app::build_sliding_model(scene, *slide, kind, {}));
    plan.sliding_model = &sliding->model();
  }
  runtime::RunResult run = app::simulate(plan).run;
  result.steps = run.statistics.steps;
  result.integrate_seconds = run.statistics.initialization_seconds + run.statistics.integration_seconds;
  if (run.samples.size() < 2) {
    result.unavailable = "stops at t0: " + std::string(run.failure ? run.failure->what() : "no step was taken");
    return result;
  }
  result.outcome = outcome_of(run);
  result.csv = result.name + ".csv";
  runtime::write_csv((dir / result.csv).string(), model, p, run.samples);
  result.constraints = check_constraints(scene, read_csv_table(dir / result.csv));
  return result;
}

/// Overlaid plots: each coordinate against t, the path, each invariant against t; a curve per model.
std::vector<Plot> comparison_plots(const std::filesystem::path& dir, const CompareSettings& settings,
                                   const PathPlane& plane, const std::vector<ComparedModel>& models,
                                   const std::vector<std::string>& invariants) {
  std::vector<std::pair<std::string, std::string>> ran;
  for (const ComparedModel& m : models)
    if (!m.csv.empty()) ran.emplace_back(m.name, m.csv);
  std::vector<Plot> plots;
  for (const std::string& q : settings.coordinates) {
    Plot p{"coordinate_" + q,
           q + " against t: " + settings.scene_name + ", models side by side",
           "t",
           q,
           false,
           false,
           {}};
    for (const auto& [name, csv] : ran) p.curves.push_back({name, csv, "t", q});
    plots.push_back(p);
  }
  if (!plane.y.empty())
    plots.push_back(
        path_plot("path", "path in the " + plane.x + "," + plane.y + " plane: " + settings.scene_name, plane, ran));
  for (const std::string& name : invariants) {
    Plot p{
        "invariant_" + name, "invariant " + name + " against t: " + settings.scene_name, "t", name, false, false, {}};
    for (const auto& [model, csv] : ran)  // a model that cannot compute it has no such column
      if (read_csv_table(dir / csv).column("invariant:" + name) >= 0)
        p.curves.push_back({model, csv, "t", "invariant:" + name});
    if (!p.curves.empty()) plots.push_back(p);
  }
  return plots;
}

int run_compare(const CompareOptions& options) {
  flag_rules::refuse_duplicates(options.models, "--models", "model");
  Scene scene = load_scene(options.scene_path);
  app::refuse_scene_controller(scene, "nhc compare");
  apply_initial_flags(scene, options.initial);  // every model starts from them
  const CompareSettings settings = settings_of(options, scene);
  const PathPlane plane = path_plane(scene, options.plot_xy, "--plot-xy");
  require_gnuplot("-o");
  AtomicDirectory out(options.output, {options.scene_path});
  const std::filesystem::path staging = out.path();

  std::vector<ComparedModel> models;
  for (ModelKind kind : selected_models(scene, options.models)) {
    models.push_back(run_model(scene, kind, settings, staging));
    const ComparedModel& m = models.back();
    std::cout << "  " << m.name << ": " << (m.csv.empty() ? m.unavailable : m.outcome) << "\n";
  }
  if (std::none_of(models.begin(), models.end(), [](const ComparedModel& m) { return !m.csv.empty(); }))
    throw MathError("nhc compare: no model of " + scene.name + " gets past t0 (see above); nothing written");

  std::vector<std::string> invariants;
  for (const SceneQuantity& invariant : scene.invariants) invariants.push_back(invariant.name);
  const std::vector<Plot> plots = comparison_plots(staging, settings, plane, models, invariants);
  draw_plots(staging, plots);
  const std::string md = compare_markdown(staging, settings, models, plots);
  write_file_atomically((staging / "compare.md").string(), [&](std::ostream& o) { o << md; });
  out.commit();
  std::cout << "nhc compare: wrote " << options.output << "/compare.md\n";
  return kExitOk;
}

}  // namespace

CommandRunner add_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* sub = app.add_subcommand(
      "compare", "integrate every model of a scene from the same initial data and compare the motions");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--models", options->models, "models to compare, comma-separated (default: the scene's)")
      ->delimiter(',')
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--t-end", options->t_end, "final time (default: [simulate] t_end)")->check(flag_rules::finite());
  sub->add_option("--rtol", options->rtol, "relative tolerance (default: [simulate] rtol)")
      ->check(flag_rules::relative_tolerance());
  sub->add_option("--atol", options->atol, "absolute tolerance (default: [simulate] atol)")
      ->check(flag_rules::absolute_tolerance());
  sub->add_option("--outputs", options->outputs, "number of output intervals (default 200)")
      ->check(flag_rules::count(1, flag_rules::kMaxOutputs));
  sub->add_option("--tolerance", options->tolerance,
                  "the motions separate where a coordinate differs by more than this (default 1e-6)")
      ->check(flag_rules::positive());
  add_initial_flag(sub, options->initial);
  sub->add_option("--plot-xy", options->plot_xy,
                  "a,b: the plane of the path plot (default: the first two coordinates)");
  sub->add_option("-o,--output", options->output, "directory for compare.md, the CSV files and the plots")->required();
  return [options]() { return run_compare(*options); };
}

}  // namespace nhc::cli
