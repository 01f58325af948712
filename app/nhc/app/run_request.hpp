#pragma once
/// \file run_request.hpp
/// \brief A run as a front end asks for it (the command line's flags, the Python module's
/// arguments) and the one place its rules are decided: output times finite, increasing and within
/// the run; tolerances finite, positive and within reach; counts positive; the variational
/// integrator's step. A value that breaks a rule is an InputError located at the field, in the
/// front end's own names for its fields (`--rtol` on the command line, `rtol` in Python).

#include <optional>
#include <string>
#include <vector>

#include "nhc/runtime/integrator.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The largest number of output intervals any run writes (a row is about 20 doubles per state;
/// 10^7 rows of a small model are already gigabytes).
inline constexpr long long kMaxOutputs = 10000000;
/// The largest limit on a run's internal steps.
inline constexpr long long kMaxSteps = 1000000000000LL;

/// How a front end names the fields of a run request in its messages.
struct FieldNames {
  std::string t_end, rtol, atol, outputs, output_times, max_steps, step, project;
  std::string variational;  ///< the request for the variational integrator ("--integrator variational")
  std::string step_value;   ///< a step written out ("--step H")
  std::string at;           ///< where the checks against the scene are located (the scene file); else the field
  std::string stop_when;    ///< the event that ends the run ("--stop-when")
  std::string sensitivity;  ///< the forward sensitivities ("--sensitivity")
  std::string inputs;       ///< inputs replaced from outside ("--input")
  std::string max_step, initial_step;  ///< IDA's largest and first step ("--max-step", "--initial-step")
};
const FieldNames& command_line_names();
const FieldNames& python_names();

/// A run's settings; an empty one takes the scene's [simulate] value.
struct RunRequest {
  std::optional<double> t_end, rtol, atol;
  std::optional<long long> outputs;                 ///< output intervals
  std::optional<std::vector<double>> output_times;  ///< explicit times (the last ends the run)
  std::string output_times_text;                    ///< as the caller wrote them, for messages
  long long max_steps = 1000000;
  bool variational = false;              ///< the discrete Lagrange–d'Alembert integrator
  std::optional<double> step;            ///< its fixed step
  bool project = false;                  ///< projection onto the hidden constraints
  std::optional<std::string> stop_when;  ///< an expression whose zero ends the run
  /// IDA's largest and first step; empty: no limit, and the first step from the problem's scale
  /// (runtime::IntegratorOptions::initial_step).
  std::optional<double> max_step, initial_step;
};

/// Why a value breaks a rule ("is not a positive number"); empty when it does not.
std::string positive_problem(double value);
std::string finite_problem(double value);
std::string relative_tolerance_problem(double value);
std::string count_problem(long long value, long long low, long long high);

/// Explicit output times: finite, increasing, from t0 on and ending after it. InputError at
/// `field` ("--output-times"), the message quoting `text` as the caller wrote the times. `t0` is
/// the run's: the scene's after its parameters are set (--set, set=) and --initial t0 is given,
/// since a t0 written through a parameter moves with it (check_run_request checks them there).
void check_output_times(const std::vector<double>& times, double t0, const std::string& field, const std::string& text);
/// The rules of output times that do not depend on the scene: finite, increasing, at least one.
void check_output_time_order(const std::vector<double>& times, const std::string& field, const std::string& text);

/// The end of a run: `t_end` when given (by the flag or keyword `field`), else the scene's
/// [simulate] t_end; either must be after the scene's t0 (a t0 from outside, `--initial t0=…`,
/// may pass the scene's own t_end: then the message says to give `field`). InputError at `where`
/// (`field` when empty) otherwise. The one rule of simulate, report, compare, ensemble and connect.
double run_t_end(const Scene& scene, const std::optional<double>& t_end, const std::string& field,
                 const std::string& where = "");

/// Every rule of `request` against the scene (t0, [simulate]) and the model: InputError naming
/// the field (in `names`) otherwise.
void check_run_request(const RunRequest& request, const Scene& scene, ModelKind kind, const FieldNames& names);

/// The output times: the request's, else t0 to t_end ([simulate] t_end) in `outputs` ([simulate]
/// outputs, else 200) equal intervals, refused where consecutive ones collapse in floating point.
std::vector<double> run_output_times(const RunRequest& request, const Scene& scene, const FieldNames& names);
/// Equally spaced output times from t0 to t_end; InputError at `fields` where they collapse.
std::vector<double> equally_spaced_output_times(double t0, double t_end, long long intervals,
                                                const std::string& fields);

/// The events of the run: the scene's [events], the lift-offs and slips of its [contacts] (contact_forces.hpp),
/// then the request's stop_when (scene_events.hpp).
/// stop_when with the variational integrator is refused (IDA locates events; the fixed-step
/// integrator does not). InputError at the field.
std::vector<SceneEvent> run_events(const RunRequest& request, const Scene& scene, const FieldNames& names);

/// IDA's options: the request's tolerances, else [simulate]'s; its steps; projection; max_steps.
runtime::IntegratorOptions run_integrator_options(const RunRequest& request, const Scene& scene);

/// A parameter value for `name` (the command line's --set, Python's set=): a parameter of the
/// scene (check_parameter_name) and a finite number. InputError at `field`; `written` is the
/// assignment as given.
void check_parameter_name(const Scene& scene, const std::string& name, const std::string& field,
                          const std::string& written);
void check_parameter_value(const Scene& scene, const std::string& name, double value, const std::string& field,
                           const std::string& written);

}  // namespace nhc::app
