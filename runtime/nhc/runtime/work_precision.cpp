#include "nhc/runtime/work_precision.hpp"

#include "nhc/base/number_text.hpp"
#include "nhc/runtime/variational.hpp"

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <sstream>

#include "nhc/runtime/trajectory.hpp"

namespace nhc::runtime {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Positions of the coordinates (order-0 states) in y.
std::vector<int> coordinate_states(const Model& model) {
  std::vector<int> idx;
  for (int c = 0; c < model.n_coordinates(); ++c) {
    const int i = model.state_index(c, 0);
    if (i >= 0) idx.push_back(i);
  }
  return idx;
}

/// max |q − q_ref| over the coordinates at the output times both runs reached.
double error_against_run(const Model& model, const std::vector<Sample>& run, const std::vector<Sample>& reference,
                         const std::vector<double>& times) {
  const std::vector<int> coords = coordinate_states(model);
  double worst = 0;
  size_t compared = 0;
  // The rows at the output times, where both runs have one (within 1e-12 relative); a row between
  // them (where an event ended a run, a contact switched) is the run's own.
  const auto output_index = [&](const Sample& s) -> long {
    const auto at = std::lower_bound(times.begin(), times.end(), s.t - 1e-12 * std::max(1.0, std::abs(s.t)));
    if (at == times.end() || std::abs(*at - s.t) > 1e-12 * std::max(1.0, std::abs(s.t))) return -1;
    return at - times.begin();
  };
  size_t k = 0, j = 0;
  while (k < run.size() && j < reference.size()) {
    const long a = output_index(run[k]), b = output_index(reference[j]);
    if (a < 0 || (b >= 0 && a < b)) {
      ++k;
    } else if (b < 0 || b < a) {
      ++j;
    } else {
      for (int i : coords) {
        const double e = std::abs(run[k].y[i] - reference[j].y[i]);
        worst = std::isfinite(e) ? std::max(worst, e) : INFINITY;
      }
      ++compared, ++k, ++j;
    }
  }
  // Only the initial point in common: nothing measured.
  return compared > 1 ? worst : NAN;
}

}  // namespace

std::string WorkPrecisionConfiguration::label() const {
  if (variational) return "variational";
  return jacobian + (projection ? " + projection" : "");
}

std::string WorkPrecisionMeasurement::status() const {
  if (!failure) return "ok";
  std::string s = to_string(*failure);
  std::replace(s.begin(), s.end(), ' ', '_');
  return s;
}

std::string ErrorSource::description() const {
  if (exact) return "the scene's [reference] (exact solution)";
  return "a reference run at rtol " + base::number_text(rtol, 3) + ", atol " + base::number_text(atol, 3) +
         " (dense LU, no projection)";
}

namespace {

/// The invariant a long run records: `energy`, else the first; -1 when the model has none.
int energy_index(const Model& model) {
  for (int k = 0; k < model.n_invariants(); ++k)
    if (std::string(model.table().invariant_names[k]) == "energy") return k;
  return model.n_invariants() > 0 ? 0 : -1;
}

InvariantHistory invariant_history(const Model& model, const std::vector<double>& p, const RunResult& run, int k,
                                   double seconds) {
  InvariantHistory h;
  h.invariant = model.table().invariant_names[k];
  h.seconds = seconds;
  h.steps = run.statistics.steps;
  if (run.failure) h.failure = run.failure->what();
  double first = NAN;
  for (const Sample& s : run.samples) {
    const double value = observe(model, p, s).invariants.at(static_cast<std::size_t>(k));
    if (std::isnan(first)) first = value;
    h.t.push_back(s.t);
    h.error.push_back(std::abs(value - first));
  }
  return h;
}

/// IDA and the variational integrator over [t0, long_run_t_end] (WorkPrecisionSettings).
std::vector<InvariantHistory> long_runs(const WorkPrecisionModels& models, double t0,
                                        const std::map<std::string, std::vector<double>>& initial_values,
                                        const std::vector<double>& p, const WorkPrecisionSettings& settings,
                                        const ProgressSink& progress) {
  std::vector<InvariantHistory> out;
  const Model& model = models.variational ? *models.variational : *models.dense;
  const int k = energy_index(model);
  if (k < 0) return out;
  const std::vector<double> times = output_times(t0, settings.long_run_t_end, settings.long_run_outputs);
  const InitialState initial = initial_state_from(model, t0, initial_values);
  IntegratorOptions io;
  io.rtol = settings.long_run_rtol;
  io.atol = settings.long_run_rtol * settings.atol_scale;
  io.max_steps = std::numeric_limits<long>::max();
  auto start = std::chrono::steady_clock::now();
  const RunResult ida =
      settings.runner ? settings.runner(model, p, initial, times, io).run : simulate(model, p, initial, times, io);
  out.push_back(invariant_history(model, p, ida, k,
                                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()));
  out.back().integrator = "IDA, rtol " + base::number_text(io.rtol, 3);
  if (models.variational && settings.long_run_step > 0) {
    const VariationalOptions vo = variational_options(settings.long_run_step, std::numeric_limits<long>::max(), io);
    start = std::chrono::steady_clock::now();
    const RunResult run = simulate_variational(model, p, initial, times, vo).run;
    out.push_back(invariant_history(model, p, run, k,
                                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()));
    out.back().integrator = "variational, step " + base::number_text(vo.step, 3);
  }
  if (progress)
    for (const InvariantHistory& h : out)
      progress("long run to t = " + base::number_text(settings.long_run_t_end, 3) + ", " + h.integrator + ": " +
               std::to_string(h.steps) + " steps, " + base::number_text(h.seconds, 3) + " s, max |" + h.invariant +
               " error| " +
               base::number_text(h.error.empty() ? NAN : *std::max_element(h.error.begin(), h.error.end()), 3));
  return out;
}

}  // namespace

WorkPrecision measure_work_precision(const WorkPrecisionModels& models, double t0,
                                     const std::map<std::string, std::vector<double>>& initial_values,
                                     const WorkPrecisionSettings& settings, const ProgressSink& progress) {
  if (!models.dense) throw base::ModelError("work-precision: the dense-Jacobian model is needed (reference runs)");
  auto model_for = [&](const std::string& jacobian) -> const Model& {
    if (jacobian == "dense") return *models.dense;
    if (jacobian == "sparse" && models.sparse) return *models.sparse;
    throw base::ModelError("work-precision: no model with the " + jacobian + " Jacobian was given");
  };
  auto variational_model = [&]() -> const Model& {
    if (!models.variational) throw base::ModelError("work-precision: no model with the variational step was given");
    return *models.variational;
  };
  const Model& dense = *models.dense;
  WorkPrecision wp;
  wp.settings = settings;
  wp.scene_name = dense.scene_name();
  wp.model_name = dense.model_name();
  const auto& tab = dense.table();
  wp.n_states = dense.n_states();
  wp.n_hidden = dense.n_hidden();
  wp.n_invariants = dense.n_invariants();
  for (int i = 0; i < dense.n_states(); ++i) wp.state_names.push_back(dense.state_name(i));
  for (int i = 0; i < dense.n_hidden(); ++i) wp.hidden_names.push_back(dense.hidden_name(i));
  for (int i = 0; i < dense.n_invariants(); ++i) wp.invariant_names.push_back(tab.invariant_names[i]);
  for (int i = 0; i < dense.n_singular(); ++i) wp.singular_names.push_back(dense.singular_name(i));
  for (int i = 0; i < dense.n_parameters(); ++i) wp.parameter_names.push_back(tab.parameter_names[i]);

  auto parameter_index = [&](const std::string& name) {
    const int i = dense.parameter_index(name);
    if (i < 0) throw base::ModelError("the model " + wp.scene_name + " has no parameter '" + name + "'");
    return i;
  };
  wp.parameters = dense.default_parameters();
  for (const auto& [name, value] : settings.parameter_overrides) wp.parameters[parameter_index(name)] = value;
  std::vector<std::optional<double>> sweep{std::nullopt};
  int sweep_index = -1;
  if (!settings.sweep_parameter.empty()) {
    sweep_index = parameter_index(settings.sweep_parameter);
    sweep.assign(settings.sweep_values.begin(), settings.sweep_values.end());
  }
  const std::vector<double> times = output_times(t0, settings.t_end, settings.outputs);
  wp.source.exact = dense.n_reference() > 0;
  wp.source.rtol = settings.reference_rtol;
  wp.source.atol = settings.reference_rtol * settings.atol_scale;

  size_t runs_per_value = 0;
  for (const WorkPrecisionConfiguration& c : settings.configurations)
    runs_per_value += c.variational ? settings.steps.size() : settings.rtols.size();
  const size_t total = sweep.size() * runs_per_value;
  size_t done = 0;
  for (const std::optional<double>& value : sweep) {
    std::vector<double> p = wp.parameters;
    if (value) p[sweep_index] = *value;
    const std::string at = value ? ", " + settings.sweep_parameter + " = " + base::number_text(*value, 6) : "";

    // The reference run: rtol = reference_rtol, loosened by decades (to 1e-10) while it does not
    // reach t_end (very tight tolerances can exhaust the step limit on stiff problems).
    std::vector<Sample> reference;
    double reference_rtol = 0;
    if (!wp.source.exact) {
      for (double rtol = settings.reference_rtol; rtol <= 1.0001e-10; rtol *= 10) {
        IntegratorOptions io;
        io.rtol = rtol;
        io.atol = rtol * settings.atol_scale;
        io.linear_solver = LinearSolverKind::dense;
        const InitialState start = initial_state_from(dense, t0, initial_values);
        const RunResult ref =
            settings.runner ? settings.runner(dense, p, start, times, io).run : simulate(dense, p, start, times, io);
        if (progress)
          progress("reference run" + at + ": rtol " + base::number_text(io.rtol, 3) + ", " +
                   std::to_string(ref.statistics.steps) + " steps" +
                   (ref.failure ? std::string(", stopped: ") + ref.failure->what() : std::string()));
        if (reference.empty() || ref.samples.size() > reference.size()) {
          reference = ref.samples;
          reference_rtol = rtol;
        }
        if (!ref.failure || ref.failure->kind() != base::FailureKind::too_many_steps) break;
      }
      wp.source.rtol = std::max(wp.source.rtol, reference_rtol);  // the loosest one used
      wp.source.atol = wp.source.rtol * settings.atol_scale;
    }

    for (const WorkPrecisionConfiguration& config : settings.configurations) {
      const Model& model = config.variational ? variational_model() : model_for(config.jacobian);
      const InitialState initial = initial_state_from(model, t0, initial_values);
      // IDA: one run per tolerance; the variational integrator: one per step.
      const std::vector<double>& series = config.variational ? settings.steps : settings.rtols;
      for (double setting : series) {
        IntegratorOptions io;
        io.rtol = config.variational ? settings.rtols.back() : setting;
        io.atol = io.rtol * settings.atol_scale;
        io.linear_solver = config.jacobian == "sparse" ? LinearSolverKind::sparse : LinearSolverKind::dense;
        io.projection = config.projection ? ProjectionMethod::in_place : ProjectionMethod::none;
        const VariationalOptions vo = variational_options(setting, std::numeric_limits<long>::max(), io);
        const auto run_once = [&]() {
          if (config.variational) return WorkPrecisionRun{simulate_variational(model, p, initial, times, vo).run, {}};
          if (settings.runner) return settings.runner(model, p, initial, times, io);
          return WorkPrecisionRun{simulate(model, p, initial, times, io), {}};
        };

        std::vector<double> seconds;
        WorkPrecisionRun made;
        RunResult& run = made.run;
        double total_seconds = 0;
        do {
          const auto start = std::chrono::steady_clock::now();
          made = run_once();
          seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
          total_seconds += seconds.back();
        } while (static_cast<int>(seconds.size()) < settings.max_repeats && total_seconds < settings.repeat_seconds);

        WorkPrecisionMeasurement m;
        m.configuration = config;
        m.sweep_value = value;
        m.rtol = config.variational ? NAN : io.rtol;
        m.atol = config.variational ? NAN : io.atol;
        m.step = config.variational ? setting : 0.0;
        m.seconds = median(seconds);
        m.repeats = static_cast<int>(seconds.size());
        m.statistics = run.statistics;
        const DriftReport drift = measure_drift(model, p, settings.runner ? made.drift_samples : run.samples);
        m.max_hidden = drift.max_hidden;
        m.max_invariant_relative = drift.max_invariant_relative;
        m.error = wp.source.exact ? (run.samples.empty() ? NAN : drift.max_error)
                                  : error_against_run(model, run.samples, reference, times);
        m.t_reached = run.samples.empty() ? t0 : run.samples.back().t;
        if (run.failure) {
          m.failure = run.failure->kind();
          m.failure_t = run.failure->t();
          m.failure_message = run.failure->what();
        }
        wp.measurements.push_back(m);
        ++done;
        if (progress)
          progress("[" + std::to_string(done) + "/" + std::to_string(total) + "] " + config.label() + at +
                   (config.variational ? ", step " : ", rtol ") + base::number_text(setting, 3) + ": error " +
                   base::number_text(m.error, 3) + ", " + std::to_string(m.statistics.steps) + " steps, " +
                   base::number_text(m.seconds, 3) + " s" + (m.failure ? ", stopped: " + m.status() : std::string()));
      }
    }
  }
  if (settings.long_run_t_end > t0)
    wp.long_runs = long_runs(models, t0, initial_values, wp.parameters, settings, progress);
  return wp;
}

}  // namespace nhc::runtime
