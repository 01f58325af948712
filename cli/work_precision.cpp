// Work-precision measurements, their CSV file and plots (work_precision.hpp).
#include "work_precision.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/app/parameter_values.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/app/scene_runs.hpp"
#include "nhc/app/switched_run.hpp"
#include "nhc/jit.hpp"
#include "nhc/tools/gnuplot.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::cli {

namespace fs = std::filesystem;

std::vector<double> decades(const std::string& flag, const std::string& spec) {
  auto parse = [&](const std::string& text) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || !(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(flag + " " + spec + ": '" + text + "' is not a positive number");
    return v;
  };
  const size_t colon = spec.find(':');
  const double hi = parse(spec.substr(0, colon));
  const double lo = colon == std::string::npos ? hi : parse(spec.substr(colon + 1));
  if (lo > hi) throw std::invalid_argument(flag + " " + spec + ": give the larger value first (1e-3:1e-12)");
  std::vector<double> values;
  // Decades: hi, hi/10, ... down to lo (inclusive within rounding), at most 20. The ratio hi/lo
  // of 1e155:1e-155 overflows; the difference of the logarithms does not.
  const double span = std::log10(hi) - std::log10(lo);
  if (span > 19 + 1e-9) throw std::invalid_argument(flag + " " + spec + ": more than 20 decades");
  const int n = static_cast<int>(std::floor(span + 1e-9));
  for (int k = 0; k <= n; ++k) values.push_back(std::stod(base::number_text(hi / std::pow(10.0, k), 12)));
  return values;
}

WorkPrecision measure_work_precision(const Scene& scene, ModelKind kind, const WorkPrecisionSettings& settings,
                                     const ProgressSink& progress) {
  // One compiled model per Jacobian flavour the configurations use (dense: also the reference run).
  WorkPrecision wp;
  std::map<std::string, jit::LoadedModel> built;
  auto build = [&](const std::string& jacobian) {
    jit::BuildOptions options;
    options.jacobian = jacobian == "sparse" ? JacobianKind::sparse : JacobianKind::dense;
    jit::LoadedModel b = jit::build(scene, kind, options);
    wp.derive_seconds += b.timings().derive + b.timings().generate + b.timings().scene_cache;
    wp.compile_seconds += b.timings().compile + b.timings().load;
    built.emplace(jacobian, std::move(b));
  };
  build("dense");
  for (const Configuration& c : settings.configurations)
    if (!c.variational && !built.count(c.jacobian)) build(c.jacobian);
  const bool variational = std::any_of(settings.configurations.begin(), settings.configurations.end(),
                                       [](const Configuration& c) { return c.variational; });
  if (variational) {  // the dense model with the variational step
    jit::BuildOptions options;
    options.jacobian = JacobianKind::dense;
    options.variational = true;
    jit::LoadedModel b = jit::build(scene, kind, options);
    wp.derive_seconds += b.timings().derive + b.timings().generate + b.timings().scene_cache;
    wp.compile_seconds += b.timings().compile + b.timings().load;
    built.emplace("variational", std::move(b));
  }
  const runtime::Model& dense = built.at("dense").model();

  const std::string scene_file = scene.source_path.empty() ? scene.name : scene.source_path;
  auto check_parameter = [&](const std::string& name) {
    if (!scene.jet->parameter_index(name))
      throw InputError({scene_file, 0, 0}, "the scene has no parameter '" + name + "'");
  };
  // A parameter the model does not read is not in its header: setting it changes nothing there
  // (app::parameters_with_overrides), sweeping it would measure one motion again and again.
  WorkPrecisionSettings read = settings;
  read.parameter_overrides.clear();
  for (const auto& [name, value] : settings.parameter_overrides) {
    check_parameter(name);
    if (dense.parameter_index(name) >= 0) read.parameter_overrides.emplace_back(name, value);
  }
  if (!settings.sweep_parameter.empty()) {
    check_parameter(settings.sweep_parameter);
    app::refuse_unread_parameter(scene, dense, settings.sweep_parameter, "--sweep", "sweeping it would change nothing");
  }

  // Every IDA run through the one run engine (app::SceneRuns::run_at): the scene's events and
  // contacts (stop and slide) as nhc simulate --set runs them, the --set values on the scene the
  // runs start from (its [initial] values, a contact's mu written through them follow).
  Scene runs_scene = scene;
  for (const auto& [name, value] : settings.parameter_overrides)
    app::check_parameter_value(scene, name, value, "--set", name + "=" + base::number_text(value, 17));
  app::set_parameter_values(runs_scene, settings.parameter_overrides);
  std::optional<jit::LoadedModel> sliding;
  if (const SceneContact* slide = app::sliding_contact(runs_scene)) {
    sliding.emplace(app::build_sliding_model(runs_scene, *slide, kind, {}));
    wp.derive_seconds += sliding->timings().derive + sliding->timings().generate + sliding->timings().scene_cache;
    wp.compile_seconds += sliding->timings().compile + sliding->timings().load;
  }
  app::FieldNames names = app::command_line_names();
  names.at = scene_file;
  const app::SceneRuns runs(runs_scene, dense, sliding ? &sliding->model() : nullptr, {}, names);
  read.runner = [&runs](const runtime::Model& model, const std::vector<double>& p, const runtime::InitialState& initial,
                        const std::vector<double>& times, const runtime::IntegratorOptions& options) {
    app::SceneRun made = runs.run_at(model, p, initial, times, options);
    return runtime::WorkPrecisionRun{std::move(made.outcome.run), std::move(made.outcome.drift_samples)};
  };

  runtime::WorkPrecisionModels models;
  models.dense = &dense;
  if (built.count("sparse")) models.sparse = &built.at("sparse").model();
  if (built.count("variational")) models.variational = &built.at("variational").model();
  static_cast<runtime::WorkPrecision&>(wp) =
      runtime::measure_work_precision(models, runs_scene.initial.t0, runs_scene.initial.values, read, progress);
  return wp;
}

void write_work_precision_csv(const std::string& path, const WorkPrecision& wp) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "configuration,jacobian,projection,parameter,value,rtol,atol,step,error,error_source,seconds,repeats,steps,"
           "residual_evaluations,jacobian_evaluations,linear_solver_setups,error_test_failures,"
           "nonlinear_iterations,nonlinear_failures,projections,max_hidden_drift,max_invariant_drift,t_end,"
           "t_reached,status\n";
    // Every number in its shortest round-trip form, as in every data file nhc writes: a program
    // reading the file gets the tolerances and swept values the runs took, bit for bit.
    const auto n = [](double v) { return base::shortest_text(v); };
    for (const Measurement& m : wp.measurements) {
      const runtime::Statistics& s = m.statistics;
      out << m.configuration.label() << ',' << m.configuration.jacobian << ',' << (m.configuration.projection ? 1 : 0)
          << ',' << (m.sweep_value ? wp.settings.sweep_parameter : "") << ',';
      if (m.sweep_value) out << n(*m.sweep_value);
      out << ',' << n(m.rtol) << ',' << n(m.atol) << ',' << n(m.step) << ',' << n(m.error) << ','
          << (wp.source.exact ? "reference" : "reference run") << ',' << n(m.seconds) << ',' << m.repeats << ','
          << s.steps << ',' << s.residual_evaluations << ',' << s.jacobian_evaluations << ',' << s.linear_solver_setups
          << ',' << s.error_test_failures << ',' << s.nonlinear_iterations << ',' << s.nonlinear_failures << ','
          << s.projections << ',' << n(m.max_hidden) << ',' << n(m.max_invariant_relative) << ','
          << n(wp.settings.t_end) << ',' << n(m.t_reached) << ',' << m.status() << '\n';
    }
  });
}

namespace {

/// Errors below this are drawn at it (a log axis has no zero).
constexpr double kPlotFloor = 1e-16;

struct WorkCurve {
  std::string title;
  std::vector<std::pair<double, double>> points;
  bool markers = true;  ///< a mark at every point (a dense history is drawn as a line)
};

void write_data(const fs::path& path, const std::vector<WorkCurve>& curves) {
  write_file_atomically(path.string(), [&](std::ostream& out) {
    for (const WorkCurve& c : curves) {
      out << tools::gnuplot_comment(c.title);
      for (const auto& [x, y] : c.points) out << base::shortest_text(x) << ' ' << base::shortest_text(y) << '\n';
      out << "\n\n";
    }
  });
}

/// The gnuplot commands for one log-log plot of `data` into `stem`.svg/.png (temporary names).
std::string plot_script(const std::string& stem, const std::string& title, const std::string& xlabel,
                        const std::string& ylabel, bool log_y, const std::vector<WorkCurve>& curves,
                        const std::string& suffix) {
  std::ostringstream g;
  g << "set terminal svg size 900,560 dynamic enhanced font 'sans,12' background rgb 'white'\n"
    << "set output " << tools::gnuplot_string(stem + ".svg" + suffix) << "\n"
    << "set title " << tools::gnuplot_string(title) << " noenhanced\n"
    << "set xlabel " << tools::gnuplot_string(xlabel) << "\nset ylabel " << tools::gnuplot_string(ylabel) << "\n"
    << "set logscale x\nset format x '10^{%L}'\n"
    << (log_y ? "set logscale y\nset format y '10^{%L}'\n" : "")
    << "set grid\nset key outside right top\nset mxtics 10\n";
  std::ostringstream plot;
  plot << "plot ";
  for (size_t i = 0; i < curves.size(); ++i)
    plot << (i ? ", \\\n     " : "") << tools::gnuplot_string(stem + ".dat") << " index " << i << " using 1:2 with "
         << (curves[i].markers ? "linespoints pointtype " + std::to_string(i % 13 + 1) : std::string("lines"))
         << " title " << tools::gnuplot_string(curves[i].title) << " noenhanced";
  g << plot.str() << "\n"
    << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
    << "  set terminal pngcairo size 900,560 enhanced font 'sans,10' background rgb 'white'\n"
    << "} else {\n"
    << "  set terminal png size 900,560 enhanced background rgb 'white'\n"
    << "}\n"
    << "set output " << tools::gnuplot_string(stem + ".png" + suffix) << "\n"
    << "replot\nset output\n";
  return g.str();
}

}  // namespace

std::vector<std::string> plot_work_precision(const std::string& directory, const WorkPrecision& wp) {
  if (const auto missing = tools::gnuplot_missing()) throw std::runtime_error(*missing + ": no plots drawn");
  const fs::path dir = directory;
  const std::string suffix = ".tmp" + std::to_string(getpid());

  // Error against time: one curve per configuration (and sweep value).
  std::vector<WorkCurve> curves;
  std::map<std::string, size_t> curve_of;
  for (const Measurement& m : wp.measurements) {
    if (!std::isfinite(m.error)) continue;
    std::string title = m.configuration.label();
    if (m.sweep_value) title += ", " + wp.settings.sweep_parameter + " = " + base::number_text(*m.sweep_value, 3);
    auto it = curve_of.find(title);
    if (it == curve_of.end()) {
      it = curve_of.emplace(title, curves.size()).first;
      curves.push_back({title, {}});
    }
    curves[it->second].points.emplace_back(std::max(m.seconds, 1e-7), std::max(m.error, kPlotFloor));
  }
  std::vector<std::pair<std::string, std::string>> scripts;
  if (!curves.empty()) {
    write_data(dir / "workprec.dat", curves);
    scripts.emplace_back("workprec",
                         plot_script("workprec",
                                     "work-precision: " + wp.scene_name + " (" + wp.model_name + "), error against " +
                                         (wp.source.exact ? "[reference]" : "a reference run"),
                                     "wall time per run [s]", "max error of the coordinates", true, curves, suffix));
  }

  // Steps against the swept parameter: one curve per configuration and tolerance.
  if (!wp.settings.sweep_parameter.empty()) {
    std::vector<WorkCurve> steps;
    std::map<std::string, size_t> steps_of;
    for (const Measurement& m : wp.measurements) {
      const std::string title = m.configuration.label() + ", rtol " + base::number_text(m.rtol, 3);
      auto it = steps_of.find(title);
      if (it == steps_of.end()) {
        it = steps_of.emplace(title, steps.size()).first;
        steps.push_back({title, {}});
      }
      steps[it->second].points.emplace_back(*m.sweep_value, static_cast<double>(m.statistics.steps));
    }
    write_data(dir / "steps.dat", steps);
    scripts.emplace_back("steps", plot_script("steps",
                                              "steps against " + wp.settings.sweep_parameter + ": " + wp.scene_name +
                                                  " (" + wp.model_name + ")",
                                              wp.settings.sweep_parameter, "IDA steps", true, steps, suffix));
  }

  // The long run: the energy error against t, both integrators on the same axes.
  if (!wp.long_runs.empty()) {
    std::vector<WorkCurve> histories;
    for (const runtime::InvariantHistory& h : wp.long_runs) {
      WorkCurve c{h.integrator, {}, false};
      for (std::size_t k = 1; k < h.t.size(); ++k)  // t0 itself has no error to draw
        c.points.emplace_back(h.t[k], std::max(h.error[k], kPlotFloor));
      histories.push_back(std::move(c));
    }
    write_data(dir / "energy.dat", histories);
    scripts.emplace_back(
        "energy",
        plot_script(
            "energy",
            "long run: " + wp.scene_name + " (" + wp.model_name + "), error of " + wp.long_runs.front().invariant, "t",
            "|" + wp.long_runs.front().invariant + "(t) - " + wp.long_runs.front().invariant + "(t0)|", true, histories,
            suffix));
  }

  std::vector<std::string> written;
  for (const auto& [stem, script] : scripts) {
    // The script is kept (without the temporary names) so that the plot can be redrawn by hand.
    std::string kept = script;
    for (size_t pos; (pos = kept.find(suffix)) != std::string::npos;) kept.erase(pos, suffix.size());
    write_file_atomically((dir / (stem + ".gp")).string(), [&](std::ostream& out) { out << kept; });
    const fs::path tmp_script = dir / (stem + ".gp" + suffix);
    // Registered, so that an interrupt stops gnuplot and removes them (nhc/io/temporary_files.hpp).
    const TemporaryFile script_file(tmp_script.string());
    const TemporaryFile svg_file((dir / (stem + ".svg" + suffix)).string());
    const TemporaryFile png_file((dir / (stem + ".png" + suffix)).string());
    {
      std::ofstream out(tmp_script);
      out << script;
    }
    std::string messages;
    const int status = tools::run_gnuplot(dir, {tmp_script.filename().string()}, messages);
    std::error_code ec;
    fs::remove(tmp_script, ec);
    for (const char* ext : {".svg", ".png"}) {
      const fs::path tmp = dir / (stem + ext + suffix), target = dir / (stem + ext);
      if (status != 0 || !fs::exists(tmp)) {
        fs::remove(tmp, ec);
        throw std::runtime_error("gnuplot failed on " + (dir / (stem + ".gp")).string() + ":\n" + messages);
      }
      fs::rename(tmp, target, ec);
      if (ec) throw std::runtime_error("cannot move " + tmp.string() + " to " + target.string() + ": " + ec.message());
      written.push_back(target.string());
    }
  }
  return written;
}

}  // namespace nhc::cli
