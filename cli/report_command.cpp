// nhc report SCENE [--model M] [--tolerances 1e-3:1e-12] [--atol-scale S] [--jacobian dense|sparse|both]
//                  [--projection off|on|both] [--t-end T] [--outputs N] [--set NAME=VALUE]...
//                  [--sweep NAME=LO:HI] [--repeats N] [--reference-rtol R] [--integrators ida,variational]
//                  [--long-run T] [--long-run-step H] [--long-run-rtol R] [-o DIR]
//
// Work-precision report of one model of a scene (work_precision.hpp): the scene integrated at
// rtol = 10^-k over the given decades with atol = rtol × scale (the scale defaults to the scene's
// [simulate] atol/rtol), in every solver configuration, error against the scene's [reference] or
// else a reference run at rtol 1e-13, wall time (median of repeats when a run takes less than
// 0.2 s), drift and solver statistics → DIR/workprec.csv, DIR/workprec.svg/.png (gnuplot),
// DIR/report.md. `--sweep K=1e2:1e8` repeats everything for K = 1e2, 1e3, …, 1e8 (the stiff
// scenes) and adds DIR/steps.svg/.png. `--integrators ida,variational` adds the variational
// integrator (docs/variational.md) at fixed steps (t_end − t0)/outputs / 2^j, j = 0..5, on the same
// axes, and a long run of both to `--long-run T` (default 100 × (t_end − t0)) whose energy error
// against t is DIR/energy.svg/.png. (docs/stability.md is written by the maintenance tool
// scripts/stability/, not by this command.)
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "nhc/app/run_engine.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/app/sampled_run.hpp"
#include "commands.hpp"
#include "nhc/app/model_requirements.hpp"
#include "flag_rules.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/jit/scene_cache.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/tolerances.hpp"
#include "nhc/base/clock.hpp"
#include "nhc/base/number_text.hpp"
#include "run_flags.hpp"
#include "work_precision.hpp"

namespace nhc::cli {

namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::string scene_path;
  std::string model;
  std::string tolerances = "1e-3:1e-12";
  std::optional<double> atol_scale, t_end;
  std::string jacobian = "both";
  std::string projection = "both";
  int outputs = 200;
  std::vector<std::string> set;
  std::vector<std::string> initial;  ///< --initial NAME=VALUE
  std::string sweep;
  int repeats = 5;
  double reference_rtol = 1e-13;
  std::string output;
  bool quiet = false;
  std::vector<std::string> integrators{"ida"};
  std::optional<double> long_run, long_run_step, long_run_rtol;
};

/// The variational integrator's steps of a report: the output interval halved 5 times.
constexpr int kVariationalStepHalvings = 5;

std::string fmt(double v, int precision = 3) {
  return std::isnan(v) ? std::string("—") : base::number_text(v, precision);
}

std::vector<double> decades_or_throw(const std::string& flag, const std::string& spec) {
  try {
    return decades(flag, spec);
  } catch (const std::invalid_argument& e) {
    throw InputError({flag, 0, 0}, e.what());
  }
}

/// The progress sink: lines on stderr once the command has run for a second (short reports stay quiet).
ProgressSink progress_sink(bool quiet) {
  if (quiet) return {};
  const auto start = base::Clock::now();
  return [start](const std::string& line) {
    if (base::seconds_since(start) > 1.0) std::cerr << "nhc report: " << line << std::endl;
  };
}

struct PreparedReport {
  Scene scene;
  ModelKind kind;
  WorkPrecisionSettings settings;
};

PreparedReport prepare(const ReportOptions& o) {
  PreparedReport r{load_scene(o.scene_path), ModelKind::chetaev, {}};
  // The runs go through the run engine (work_precision.cpp): events and contacts compose; a
  // controller's rows would be its samples, not the report's output times.
  app::refuse_scene_controller(r.scene, "nhc report");
  apply_initial_flags(r.scene, o.initial);
  // The scene's [reference] solves the motion from its own [initial]: from other values the error
  // is measured against a reference run.
  if (!o.initial.empty()) r.scene.reference = {};
  r.kind = model_or_default(r.scene, o.model);
  app::require_model_inputs(r.scene, r.kind);
  WorkPrecisionSettings& s = r.settings;
  s.rtols = decades_or_throw("--tolerances", o.tolerances);
  for (double rtol : s.rtols)
    if (const std::string problem = relative_tolerance_problem(rtol); !problem.empty())
      throw InputError({"--tolerances", 0, 0}, "--tolerances " + o.tolerances + ": rtol " + fmt(rtol) + " " + problem);
  if (const std::string problem = relative_tolerance_problem(o.reference_rtol); !problem.empty())
    throw InputError({"--reference-rtol", 0, 0}, "--reference-rtol " + fmt(o.reference_rtol) + " " + problem);
  s.atol_scale = o.atol_scale.value_or(r.scene.simulate.atol / r.scene.simulate.rtol);
  s.t_end = app::run_t_end(r.scene, o.t_end, "--t-end", o.scene_path);  // located as simulate's
  s.outputs = o.outputs;
  flag_rules::output_times(r.scene.initial.t0, s.t_end, s.outputs, "--t-end/--outputs");  // they must not collapse
  s.max_repeats = o.repeats;
  s.reference_rtol = o.reference_rtol;
  const auto uses = [&](const std::string& integrator) {
    return std::find(o.integrators.begin(), o.integrators.end(), integrator) != o.integrators.end();
  };
  if (uses("ida"))
    for (const std::string& j : {std::string("dense"), std::string("sparse")}) {
      if (o.jacobian != "both" && o.jacobian != j) continue;
      for (bool projection : {false, true})
        if (o.projection == "both" || (o.projection == "on") == projection)
          s.configurations.push_back({j, projection, false});
    }
  if (uses("variational")) {
    require_variational_scene(r.scene, r.kind);
    app::RunFeatures features;  // the engine's refusals: the fixed-step integrator locates no events
    features.variational = true;
    app::FieldNames names = app::command_line_names();
    names.variational = "--integrators variational";
    app::check_run_features(r.scene, features, names);
    s.configurations.push_back({"dense", false, true});
    const double interval = (s.t_end - r.scene.initial.t0) / s.outputs;
    for (int j = 0; j <= kVariationalStepHalvings; ++j) s.steps.push_back(interval / std::pow(2.0, j));
    s.long_run_t_end = r.scene.initial.t0 + o.long_run.value_or(100 * (s.t_end - r.scene.initial.t0));
    if (!(s.long_run_t_end > r.scene.initial.t0))
      throw InputError({"--long-run", 0, 0}, "--long-run " + fmt(*o.long_run, 6) + " must be positive");
    s.long_run_step = o.long_run_step.value_or(s.steps.at(1));
    s.long_run_rtol = o.long_run_rtol.value_or(r.scene.simulate.rtol);
    const long steps = runtime::variational_steps_needed(r.scene.initial.t0, s.long_run_t_end, s.long_run_step);
    if (steps < 0 || steps > 100000000)
      throw InputError({"--long-run-step", 0, 0}, "the long run takes " +
                                                      (steps < 0 ? std::string("too many") : std::to_string(steps)) +
                                                      " variational steps, more than 10^8");
  } else if (o.long_run || o.long_run_step || o.long_run_rtol) {
    throw InputError({"--long-run", 0, 0},
                     "--long-run compares IDA with the variational integrator: add "
                     "--integrators ida,variational");
  }
  for (const std::string& a : o.set) {
    const auto [name, value] = app::split_assignment("--set", a);
    s.parameter_overrides.emplace_back(name, app::parse_number("--set", value, a));
  }
  if (!o.sweep.empty()) {
    const auto [name, range] = app::split_assignment("--sweep", o.sweep);
    s.sweep_parameter = name;
    s.sweep_values = decades_or_throw("--sweep", range);
    std::reverse(s.sweep_values.begin(), s.sweep_values.end());  // LO:HI → increasing
  }
  return r;
}

/// Accepts both orders for a sweep (K=1e2:1e8 or K=1e8:1e2); decades() wants the larger first.
std::string normalized_sweep(const std::string& sweep) {
  const size_t eq = sweep.find('='), colon = sweep.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos) return sweep;
  const std::string lo = sweep.substr(eq + 1, colon - eq - 1), hi = sweep.substr(colon + 1);
  try {
    if (std::stod(lo) < std::stod(hi)) return sweep.substr(0, eq + 1) + hi + ":" + lo;
  } catch (const std::exception&) {
  }
  return sweep;
}

// ---------------------------------------------------------------------------------------------
// report.md

std::string table_row(const std::vector<std::string>& cells) {
  std::string row = "|";
  for (const std::string& c : cells) row += " " + c + " |";
  return row + "\n";
}

/// Per configuration (and sweep value): how the error falls with the tolerance.
std::string error_summary(const WorkPrecision& wp) {
  std::ostringstream out;
  std::map<std::string, std::vector<const Measurement*>> series;
  std::vector<std::string> order;
  for (const Measurement& m : wp.measurements) {
    std::string key = m.configuration.label();
    if (m.sweep_value) key += ", " + wp.settings.sweep_parameter + " = " + fmt(*m.sweep_value);
    if (!series.count(key)) order.push_back(key);
    series[key].push_back(&m);
  }
  for (const std::string& key : order) {
    const auto& ms = series[key];
    double best = INFINITY;
    for (const Measurement* m : ms)
      if (std::isfinite(m->error)) best = std::min(best, m->error);
    if (!std::isfinite(best)) {
      out << "- " << key << ": no error could be measured.\n";
      continue;
    }
    if (ms.front()->configuration.variational) {
      // Fixed steps, halved: the observed order of each halving, log2 of the error ratio.
      out << "- " << key << ": error " << fmt(ms.front()->error) << " at step " << fmt(ms.front()->step) << ", "
          << fmt(ms.back()->error) << " at step " << fmt(ms.back()->step) << "; observed orders";
      for (std::size_t k = 1; k < ms.size(); ++k)
        out << (k > 1 ? "," : "") << " " << fmt(std::log2(ms[k - 1]->error / ms[k]->error), 3);
      out << " (the midpoint rule's order is 2).\n";
      continue;
    }
    // The loosest tolerance from which on the error stays within 10× of the best: the floor.
    double floor_rtol = ms.back()->rtol;
    for (auto it = ms.rbegin(); it != ms.rend(); ++it) {
      if (!std::isfinite((*it)->error) || (*it)->error > 10 * std::max(best, 1e-300)) break;
      floor_rtol = (*it)->rtol;
    }
    out << "- " << key << ": error " << fmt(ms.front()->error) << " at rtol " << fmt(ms.front()->rtol) << ", "
        << fmt(ms.back()->error) << " at rtol " << fmt(ms.back()->rtol) << "; smallest " << fmt(best)
        << ", reached (within 10×) from rtol " << fmt(floor_rtol) << " on.\n";
  }
  return out.str();
}

/// The model's equations as `nhc derive` writes them, from the scene cache when the scene is
/// unchanged (nhc/jit/scene_cache.hpp).
std::string derivation_text(const Scene& scene, ModelKind kind) {
  const std::optional<std::string> key =
      jit::scene_cache_enabled() ? jit::scene_cache_key(scene, "derivation text", "model " + to_string(kind))
                                 : std::nullopt;
  std::optional<jit::SceneCache> cache;
  if (key) {
    cache.emplace();
    if (const std::optional<jit::SceneCacheRecord> record = cache->load(*key))
      if (std::optional<std::string> text = record->get("text")) return *text;
  }
  std::ostringstream equations;
  write_derivation_text(equations, scene, {derive_model(scene, kind)});
  if (key) {
    jit::SceneCacheRecord record;
    record.set("text", equations.str());
    cache->store(*key, record);
  }
  return equations.str();
}

void write_report(const std::string& path, const Scene& scene, ModelKind kind, const WorkPrecision& wp,
                  const std::vector<std::string>& images, const std::vector<std::string>& initial) {
  const std::string equations = derivation_text(scene, kind);
  const WorkPrecisionSettings& s = wp.settings;
  const bool sweep = !s.sweep_parameter.empty();

  write_file_atomically(path, [&](std::ostream& out) {
    out << "# Work-precision report: " << wp.scene_name << " (" << wp.model_name << ")\n\n"
        << "Written by `nhc report` from `" << scene.source_path << "`.\n\n"
        << "## Settings\n\n"
        << "- t from " << fmt(scene.initial.t0, 6) << " to " << fmt(s.t_end, 6) << "; error and drift measured at "
        << s.outputs + 1 << " equally spaced output times.\n"
        << "- rtol = " << fmt(s.rtols.front()) << " … " << fmt(s.rtols.back()) << " by decades, atol = rtol × "
        << fmt(s.atol_scale) << " (the scale is the scene's [simulate] atol/rtol unless `--atol-scale` is given).\n"
        << "- error: max over the output times and the coordinates of |q − q_ref|, against " << wp.source.description()
        << ". A run that stops early is compared up to where it stopped.\n"
        << "- seconds: wall time of one run (consistent initialization and integration; not derivation or "
           "compilation), the median of up to "
        << s.max_repeats << " repeats while their total stays below " << fmt(s.repeat_seconds) << " s.\n"
        << "- drift: max |g_i| of the hidden constraints, and max over the invariants of |I(t) − I(t0)| / |I(t0)|.\n"
        << "- configurations: dense LU or KLU (sparse) with the generated Jacobian, without or with projection "
           "onto the hidden constraints (`in_place`, docs/projection.md).\n";
    if (!s.steps.empty())
      out << "- variational: the discrete Lagrange–d'Alembert integrator (docs/variational.md) at the fixed steps "
          << fmt(s.steps.front()) << " … " << fmt(s.steps.back()) << " (halving), its initial point consistent at rtol "
          << fmt(s.rtols.back()) << ".\n";
    if (!s.parameter_overrides.empty()) {
      out << "- parameters set:";
      for (const auto& [n, v] : s.parameter_overrides) out << " " << n << " = " << fmt(v, 6);
      out << "\n";
    }
    if (!initial.empty()) {
      out << "- initial values set (as if written in [initial]):";
      for (const std::string& a : initial) out << " `" << a << "`";
      out << "\n";
    }
    if (sweep)
      out << "- sweep: " << s.sweep_parameter << " = " << fmt(s.sweep_values.front()) << " … "
          << fmt(s.sweep_values.back()) << " by decades.\n";
    out << "- derivation and code generation " << fmt(wp.derive_seconds) << " s, compilation "
        << fmt(wp.compile_seconds) << " s (not in the table).\n\n";

    out << "## Plots\n\n";
    for (const std::string& image : images)
      if (fs::path(image).extension() == ".svg")
        out << "![" << fs::path(image).stem().string() << "](" << fs::path(image).filename().string() << ")\n\n";
    if (images.empty()) out << "(not drawn: gnuplot missing)\n\n";
    out << "Errors below 1e-16 are drawn at 1e-16.\n\n";

    out << "## Error against tolerance\n\n" << error_summary(wp) << "\n";
    if (!wp.long_runs.empty()) {
      out << "## Long run\n\n"
          << "From t = " << fmt(scene.initial.t0, 6) << " to " << fmt(s.long_run_t_end, 6) << ", "
          << s.long_run_outputs + 1 << " samples; the error of the invariant `" << wp.long_runs.front().invariant
          << "`, |I(t) − I(t0)|:\n\n"
          << table_row({"integrator", "steps", "seconds", "max error", "error at the end", "status"})
          << table_row({"---", "---", "---", "---", "---", "---"});
      for (const runtime::InvariantHistory& h : wp.long_runs)
        out << table_row({h.integrator, std::to_string(h.steps), fmt(h.seconds),
                          fmt(h.error.empty() ? NAN : *std::max_element(h.error.begin(), h.error.end())),
                          fmt(h.error.empty() ? NAN : h.error.back()), h.failure.empty() ? "ok" : h.failure});
      out << "\n";
    }

    out << "## Measurements\n\n";
    std::vector<std::string> header{"configuration"};
    if (sweep) header.push_back(s.sweep_parameter);
    for (const char* h : {"rtol", "atol", "step", "error", "seconds", "repeats", "steps", "residuals", "Jacobians",
                          "error-test failures", "nonlinear failures", "projections", "hidden drift", "invariant drift",
                          "t reached", "status"})
      header.push_back(h);
    out << table_row(header);
    out << table_row(std::vector<std::string>(header.size(), "---"));
    for (const Measurement& m : wp.measurements) {
      const runtime::Statistics& st = m.statistics;
      std::vector<std::string> row{m.configuration.label()};
      if (sweep) row.push_back(fmt(*m.sweep_value));
      for (const std::string& c :
           {fmt(m.rtol), fmt(m.atol), m.step > 0 ? fmt(m.step) : std::string("—"), fmt(m.error), fmt(m.seconds),
            std::to_string(m.repeats), std::to_string(st.steps), std::to_string(st.residual_evaluations),
            std::to_string(st.jacobian_evaluations), std::to_string(st.error_test_failures),
            std::to_string(st.nonlinear_failures), std::to_string(st.projections), fmt(m.max_hidden),
            fmt(m.max_invariant_relative), fmt(m.t_reached, 6), m.status()})
        row.push_back(c);
      out << table_row(row);
    }
    out << "\nThe same numbers are in `workprec.csv`.\n\n";

    // Failures, once per distinct message.
    std::vector<std::string> messages;
    for (const Measurement& m : wp.measurements)
      if (m.failure && std::find(messages.begin(), messages.end(), m.failure_message) == messages.end())
        messages.push_back(m.failure_message);
    if (!messages.empty()) {
      out << "## Stops\n\n";
      for (const std::string& msg : messages) out << "- " << msg << "\n";
      out << "\n";
    }

    out << "## Solver statistics\n\n";
    if (!wp.measurements.empty()) {
      const runtime::Statistics& st = wp.measurements.back().statistics;
      out << "Linear solver and Jacobian per configuration: ";
      std::vector<std::string> seen;
      for (const Measurement& m : wp.measurements) {
        const std::string d =
            m.configuration.label() + ": " + m.statistics.linear_solver + ", " + m.statistics.jacobian;
        if (std::find(seen.begin(), seen.end(), d) == seen.end()) seen.push_back(d);
      }
      for (size_t i = 0; i < seen.size(); ++i) out << (i ? "; " : "") << seen[i];
      out << ".\n\nTightest run of the last configuration: " << st.steps << " steps, " << st.residual_evaluations
          << " residual evaluations, " << st.jacobian_evaluations << " Jacobian evaluations, "
          << st.linear_solver_setups << " linear-solver set-ups, " << st.nonlinear_iterations
          << " nonlinear iterations, " << st.error_test_failures << " error-test failures, " << st.nonlinear_failures
          << " nonlinear failures, " << st.root_evaluations << " root evaluations, " << st.projections
          << " projections.\n\n";
    }

    out << "## Equations\n\n"
        << "Index-1 system: " << wp.n_states << " states (";
    for (size_t i = 0; i < wp.state_names.size(); ++i) out << (i ? ", " : "") << "`" << wp.state_names[i] << "`";
    out << "), " << wp.n_hidden << " hidden constraints";
    if (!wp.hidden_names.empty()) {
      out << " (";
      for (size_t i = 0; i < wp.hidden_names.size(); ++i) out << (i ? ", " : "") << "`" << wp.hidden_names[i] << "`";
      out << ")";
    }
    out << ".";
    if (!wp.singular_names.empty()) {
      out << " Singular-set monitors: ";
      for (size_t i = 0; i < wp.singular_names.size(); ++i)
        out << (i ? ", " : "") << "`" << wp.singular_names[i] << "`";
      out << ".";
    }
    out << "\n\nParameters:";
    for (size_t i = 0; i < wp.parameter_names.size(); ++i)
      out << (i ? "," : "") << " " << wp.parameter_names[i] << " = " << fmt(wp.parameters[i], 6);
    out << "\n\n```\n" << equations << "```\n";
  });
}

int run_report(const ReportOptions& o) {
  if (o.scene_path.empty()) throw InputError({"SCENE", 0, 0}, "nhc report needs a SCENE");
  ReportOptions opts = o;
  opts.sweep = normalized_sweep(o.sweep);
  const PreparedReport prepared = prepare(opts);
  // Built in a temporary sibling and moved into place at the end (nhc/io/atomic_directory.hpp).
  AtomicDirectory dir(o.output.empty() ? prepared.scene.name + "-report" : o.output, {o.scene_path});

  const WorkPrecision wp =
      measure_work_precision(prepared.scene, prepared.kind, prepared.settings, progress_sink(o.quiet));
  write_work_precision_csv(dir.file("workprec.csv"), wp);
  std::vector<std::string> images;
  std::string plot_error;
  try {
    images = plot_work_precision(dir.path(), wp);
  } catch (const std::runtime_error& e) {
    plot_error = e.what();
  }
  write_report(dir.file("report.md"), prepared.scene, prepared.kind, wp, images, o.initial);
  dir.commit();
  if (!o.quiet) {
    std::cout << "nhc report: " << wp.scene_name << " (" << wp.model_name << "), " << wp.measurements.size()
              << " runs, error against " << wp.source.description() << "\n";
    for (const std::string& f : {std::string("workprec.csv"), std::string("report.md")})
      std::cout << "  wrote " << dir.final_file(f) << "\n";
    for (const std::string& f : images)
      std::cout << "  wrote " << dir.final_file(fs::path(f).filename().string()) << "\n";
  }
  if (!plot_error.empty()) throw EnvironmentError(plot_error);
  return kExitOk;
}

}  // namespace

CommandRunner add_report_command(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* sub = app.add_subcommand(
      "report", "work-precision report of one model of a scene: error against run time over a range of tolerances");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--tolerances", options->tolerances, "rtol range by decades, loosest first (default 1e-3:1e-12)");
  sub->add_option("--atol-scale", options->atol_scale, "atol = rtol × this (default: the scene's atol/rtol)")
      ->check(flag_rules::positive());
  sub->add_option("--jacobian", options->jacobian, "dense, sparse or both (default both)")
      ->check(CLI::IsMember({"dense", "sparse", "both"}));
  sub->add_option("--projection", options->projection, "off, on or both (default both)")
      ->check(CLI::IsMember({"off", "on", "both"}));
  sub->add_option("--t-end", options->t_end, "final time (default: [simulate] t_end)")->check(flag_rules::finite());
  sub->add_option("--outputs", options->outputs, "output intervals where error and drift are measured (default 200)")
      ->check(flag_rules::count(1, flag_rules::kMaxOutputs));
  add_set_option(sub, options->set);
  add_initial_flag(sub, options->initial);
  sub->add_option("--sweep", options->sweep, "NAME=LO:HI: repeat for the parameter at every decade from LO to HI");
  sub->add_option("--repeats", options->repeats, "at most this many timed repeats of a short run (default 5)")
      ->check(flag_rules::count(1, 1000));
  sub->add_option("--reference-rtol", options->reference_rtol,
                  "rtol of the reference run for scenes without [reference] (default 1e-13)")
      ->check(flag_rules::relative_tolerance());
  sub->add_option("-o,--output", options->output,
                  "directory for workprec.csv, workprec.svg/.png and report.md (default <scene>-report)");
  sub->add_flag("-q,--quiet", options->quiet, "no summary and no progress lines");
  sub->add_option("--integrators", options->integrators,
                  "ida, variational or both (comma-separated; default ida): variational adds the discrete "
                  "Lagrange-d'Alembert integrator at fixed steps, and a long run of both (docs/variational.md)")
      ->delimiter(',')
      ->check(CLI::IsMember({"ida", "variational"}));
  sub->add_option("--long-run", options->long_run,
                  "length of the long run comparing the energy error of both integrators (default 100 x the span)")
      ->check(flag_rules::positive());
  sub->add_option("--long-run-step", options->long_run_step,
                  "the variational integrator's step in the long run (default the second of its series)")
      ->check(flag_rules::positive());
  sub->add_option("--long-run-rtol", options->long_run_rtol, "IDA's rtol in the long run (default: [simulate] rtol)")
      ->check(flag_rules::relative_tolerance());

  return [options]() { return run_report(*options); };
}

}  // namespace nhc::cli
