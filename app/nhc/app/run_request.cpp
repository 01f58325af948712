#include "run_request.hpp"

#include <cmath>
#include <sstream>

#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/app/contact_forces.hpp"
#include "nhc/app/parameter_values.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/jet_space.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/runtime/variational.hpp"
#include "nhc/scene/tolerances.hpp"

namespace nhc::app {

namespace {

/// A number with `precision` significant digits, as the messages have always written them.
std::string number(double v, int precision) {
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

/// The location of a field's message: the field itself ("--rtol"), in the words of flag_rules.
[[noreturn]] void refuse(const std::string& field, const std::string& message) {
  throw InputError({field, 0, 0}, message);
}

void check_value(const std::string& field, double value, std::string (*problem)(double)) {
  if (const std::string why = problem(value); !why.empty()) refuse(field, field + ": " + number(value, 17) + " " + why);
}

void check_count(const std::string& field, long long value, long long low, long long high) {
  if (const std::string why = count_problem(value, low, high); !why.empty())
    refuse(field, field + ": " + std::to_string(value) + " " + why);
}

}  // namespace

const FieldNames& command_line_names() {
  static const FieldNames names{"--t-end",
                                "--rtol",
                                "--atol",
                                "--outputs",
                                "--output-times",
                                "--max-steps",
                                "--step",
                                "--project",
                                "--integrator variational",
                                "--step H",
                                "",
                                "--stop-when",
                                "--sensitivity",
                                "--input",
                                "--max-step",
                                "--initial-step"};
  return names;
}

const FieldNames& python_names() {
  static const FieldNames names{"t_end",
                                "rtol",
                                "atol",
                                "outputs",
                                "output_times",
                                "max_steps",
                                "step",
                                "project",
                                "integrator='variational'",
                                "step=H",
                                "",
                                "stop_when",
                                "sensitivity",
                                "inputs",
                                "max_step",
                                "initial_step"};
  return names;
}

std::string positive_problem(double v) { return std::isfinite(v) && v > 0 ? "" : "is not a positive number"; }
std::string finite_problem(double v) { return std::isfinite(v) ? "" : "is not a finite number"; }
std::string relative_tolerance_problem(double v) {
  const std::string why = nhc::relative_tolerance_problem(v);
  return why.empty() || why != "must be a positive number" ? why : "is not a positive number";
}
std::string count_problem(long long value, long long low, long long high) {
  if (value >= low && value <= high) return "";
  return "is not a whole number from " + std::to_string(low) + " to " + std::to_string(high);
}

void check_output_time_order(const std::vector<double>& times, const std::string& field, const std::string& text) {
  const auto bad = [&](const std::string& why) { refuse(field, field + " " + text + ": " + why); };
  for (double t : times)
    if (!std::isfinite(t)) bad(base::shortest_text(t) + " is not a finite number");
  for (std::size_t i = 1; i < times.size(); ++i)
    if (!(times[i] > times[i - 1])) bad("the times must increase");
  if (times.empty()) bad("no time");
}

void check_output_times(const std::vector<double>& times, double t0, const std::string& field,
                        const std::string& text) {
  check_output_time_order(times, field, text);
  const auto bad = [&](const std::string& why) { refuse(field, field + " " + text + ": " + why); };
  if (times.front() < t0) bad("the first time is before t0 = " + base::shortest_text(t0));
  if (!(times.back() > t0)) bad("the last time must be after t0 = " + base::shortest_text(t0));
}

double run_t_end(const Scene& scene, const std::optional<double>& t_end, const std::string& field,
                 const std::string& where) {
  using base::shortest_text;  // 0.2, not 0.20000000000000001
  const std::string& at = where.empty() ? field : where;
  const double t0 = scene.initial.t0;
  if (t_end && !(*t_end > t0))
    refuse(at, field + " " + base::shortest_text(*t_end) + " must be after t0 = " + base::shortest_text(t0));
  // The scene's own t_end is after its own t0 (scene_loader.cpp); a t0 from outside may pass it.
  const NumberExpression& written = scene.simulate.t_end_expression;
  if (!t_end && !(scene.simulate.t_end > t0) && !written.empty())  // t_end = "Tend" at the parameters set
    throw InputError(written.where, "t_end = \"" + written.text + "\" is " + base::shortest_text(scene.simulate.t_end) +
                                        ", not after t0 = " + base::shortest_text(t0) + ": give " + field +
                                        " or other parameter values");
  if (!t_end && !(scene.simulate.t_end > t0))
    refuse(at, "the scene's [simulate] t_end " + base::shortest_text(scene.simulate.t_end) +
                   " is not after t0 = " + base::shortest_text(t0) + ": give " + field);
  return t_end.value_or(scene.simulate.t_end);
}

void check_run_request(const RunRequest& r, const Scene& scene, ModelKind kind, const FieldNames& names) {
  if (r.t_end) check_value(names.t_end, *r.t_end, finite_problem);
  if (r.rtol) check_value(names.rtol, *r.rtol, relative_tolerance_problem);
  if (r.atol) check_value(names.atol, *r.atol, positive_problem);
  if (r.step) check_value(names.step, *r.step, positive_problem);
  if (r.max_step) check_value(names.max_step, *r.max_step, positive_problem);
  if (r.initial_step) check_value(names.initial_step, *r.initial_step, positive_problem);
  if (r.variational && (r.max_step || r.initial_step))
    refuse(r.max_step ? names.max_step : names.initial_step, (r.max_step ? names.max_step : names.initial_step) +
                                                                 " sets IDA's steps; " + names.variational +
                                                                 " takes the fixed step " + names.step_value);
  if (r.outputs) check_count(names.outputs, *r.outputs, 1, kMaxOutputs);
  check_count(names.max_steps, r.max_steps, 1, kMaxSteps);
  if (r.output_times) check_output_times(*r.output_times, scene.initial.t0, names.output_times, r.output_times_text);
  const std::string here = names.at.empty() ? names.t_end : names.at;
  if (r.t_end || !r.output_times) run_t_end(scene, r.t_end, names.t_end, here);  // output times end the run otherwise
  const std::string at_step = names.at.empty() ? names.step : names.at;
  if (!r.variational) {
    if (r.step) refuse(at_step, names.step + " is the fixed step of " + names.variational + "; IDA chooses its own");
    return;
  }
  if (!r.step) refuse(at_step, names.variational + " needs " + names.step_value + " (the fixed step)");
  if (r.project)
    refuse(names.at.empty() ? names.project : names.at,
           names.project + " applies to IDA: the variational integrator solves the discrete constraints at every step");
  require_variational_scene(scene, kind);
  const double t_end = run_output_times(r, scene, names).back();
  if (!runtime::variational_step_fits(scene.initial.t0, t_end, *r.step))
    refuse(at_step, names.step + " " + number(*r.step, 6) +
                        " does not fit the run from t0 = " + number(scene.initial.t0, 6) + " to " + number(t_end, 6) +
                        " twice: the variational integrator needs at least two steps");
  const long steps = runtime::variational_steps_needed(scene.initial.t0, t_end, *r.step);
  if (steps < 0 || steps > r.max_steps)
    refuse(at_step, names.step + " " + number(*r.step, 6) + " takes " +
                        (steps < 0 ? std::string("too many") : std::to_string(steps)) + " steps to t = " +
                        number(t_end, 6) + ", more than " + names.max_steps + " " + std::to_string(r.max_steps));
}

std::vector<SceneEvent> run_events(const RunRequest& r, const Scene& scene, const FieldNames& names) {
  std::vector<SceneEvent> events = scene.events;
  const std::vector<SceneEvent> slips = slip_events(scene);  // [contacts]: lift-off, and slip where on_slip = "stop"
  events.insert(events.end(), slips.begin(), slips.end());
  if (!r.stop_when) return events;
  if (r.variational)
    refuse(names.stop_when, names.stop_when + ": events are located by IDA's root finding; " + names.variational +
                                " takes fixed steps and locates none");
  events.push_back(stop_when_event(scene, *r.stop_when, names.stop_when));
  return events;
}

std::vector<double> equally_spaced_output_times(double t0, double t_end, long long intervals,
                                                const std::string& fields) {
  std::vector<double> times = runtime::output_times(t0, t_end, static_cast<int>(intervals));
  if (const auto i = runtime::collapsed_output_time(times)) {
    std::ostringstream why;
    why.precision(17);
    why << intervals << " output intervals from t0 = " << t0 << " to t_end = " << t_end
        << " are closer than double precision resolves (times " << *i - 1 << " and " << *i << " are both "
        << times[*i - 1] << "): choose fewer intervals or a span nearer the times' size";
    refuse(fields, why.str());
  }
  return times;
}

std::vector<double> run_output_times(const RunRequest& r, const Scene& scene, const FieldNames& names) {
  const double t0 = scene.initial.t0;
  if (r.output_times) {
    check_output_times(*r.output_times, t0, names.output_times, r.output_times_text);
    return *r.output_times;
  }
  return equally_spaced_output_times(t0, r.t_end.value_or(scene.simulate.t_end),
                                     r.outputs.value_or(scene.simulate.outputs.value_or(200)),
                                     names.t_end + "/" + names.outputs);
}

runtime::IntegratorOptions run_integrator_options(const RunRequest& r, const Scene& scene) {
  runtime::IntegratorOptions io;
  io.rtol = r.rtol.value_or(scene.simulate.rtol);
  io.atol = r.atol.value_or(scene.simulate.atol);
  io.projection = r.project ? runtime::ProjectionMethod::in_place : runtime::ProjectionMethod::none;
  io.max_steps = static_cast<long>(r.max_steps);
  // The flags, else [simulate]'s; 0: no limit, and the first step from the problem's scale
  // (runtime::IntegratorOptions).
  io.max_step = r.max_step.value_or(scene.simulate.max_step.value_or(0));
  io.initial_step = r.initial_step.value_or(scene.simulate.initial_step.value_or(0));
  return io;
}

void check_parameter_name(const Scene& scene, const std::string& name, const std::string& field,
                          const std::string& written) {
  if (const DerivedParameter* derived = scene.derived_parameter(name)) {
    std::ostringstream formula;
    formula << derived->value;
    refuse(field, written + ": the scene computes '" + name + "' from other parameters (" + name + " = " +
                      formula.str() + "): set those instead");
  }
  if (!scene.jet->parameter_index(name)) {
    std::string known;
    for (const std::string& p : scene.jet->parameters()) known += (known.empty() ? "" : ", ") + p;
    // A key of the scene's experiment (mu, period, t_end, …) is a number at its place, which a
    // parameter written there moves.
    std::string key;
    for_each_experiment_number(scene, [&](const std::string& what, const NumberExpression& number) {
      const bool named = what.rfind(name + " ", 0) == 0 ||
                         (what.size() > name.size() &&
                          what.compare(what.size() - name.size() - 1, std::string::npos, " " + name) == 0);
      if (key.empty() && named && number.where.line > 0)
        key = ": it is the scene's " + what + " (" + number.where.str() + ")" +
              (number.empty() ? "; to move it with " + field + ", write it there through a parameter (" + name +
                                    " = \"NAME\", NAME in [parameters]) and set that"
                              : ", written \"" + number.text + "\": set the parameters it uses");
    });
    refuse(field, written + ": '" + name + "' is not a parameter of the scene (" +
                      (known.empty() ? std::string("it has none") : "parameters: " + known) + ")" + key);
  }
}

void check_parameter_value(const Scene& scene, const std::string& name, double value, const std::string& field,
                           const std::string& written) {
  check_parameter_name(scene, name, field, written);
  if (!std::isfinite(value)) refuse(field, written + ": " + number(value, 17) + " is not a finite number");
}

}  // namespace nhc::app
