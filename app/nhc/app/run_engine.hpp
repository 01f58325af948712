#pragma once
/// \file run_engine.hpp
/// \brief The one run engine (docs/combinations.md): every front end that integrates a scene
/// (nhc simulate, animate, Python's Model.simulate) hands it a RunPlan and presents the RunOutcome.
/// One hybrid loop owns the run: the sampled controller's samples, the events' roots and a sliding
/// contact's slip and stick are all boundaries of its segments, so they compose by construction;
/// a combination that cannot is refused by check_run_features, in words, once for every front end.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nhc/app/run_request.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/app/switched_run.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// What a run combines, as the engine judges the combination before anything is built.
struct RunFeatures {
  bool controller = false;       ///< a sampled controller: the scene's [controller] or a front end's function
  std::string controller_name;   ///< as messages name it ("the scene's [controller]", "the controller")
  std::string controller_where;  ///< where it is (the table's FILE:L:C, "controller=")
  std::vector<std::string> controlled_inputs;  ///< the inputs the controller sets (empty with held-all)
  bool controls_all_inputs = false;            ///< a front end's controller returns every input
  bool mpc = false;                            ///< the controller is model predictive control (mpc_controller.hpp)
  std::vector<std::string> replaced_inputs;    ///< inputs an --input / inputs= replaces
  bool inputs_function = false;                ///< a front end's u(t, y) for every input (Python's inputs=)
  bool sensitivities = false;
  bool variational = false;
  bool outputs = false, output_times = false;  ///< output times asked for (a controller's rows are its samples)
};

/// The refusals of the engine (InputError at the field, in `names`' words): a sampled controller
/// with --sensitivity or with an --input of an input it sets; the variational integrator with
/// events or contacts (it takes fixed steps and locates no roots); sensitivities with an event that
/// ends the run or a contact's slip (IDAS runs through to t_end, the derivative of a switching
/// time is not computed); model predictive control with a contact (its plans know no contact
/// force). `scene` is the run's scene (its [events], [contacts]).
void check_run_features(const Scene& scene, const RunFeatures& features, const FieldNames& names);

/// A sampled controller of a run.
struct RunControl {
  SampleLaw law;
  std::vector<bool> held;       ///< the inputs it holds (empty: all)
  std::vector<double> samples;  ///< its sample times t0 + k h (sample_times): the run's rows
  double period = 0;
  /// The scene's [controller] (its state columns), null for a front end's function.
  std::shared_ptr<ControllerLaws> scene_laws;
  /// Without scene_laws: the controller's own columns of each row (model predictive control's
  /// mpc:cost …), the values of the sample just taken (`at_sample`) or of a row that is none.
  std::function<std::vector<double>(bool at_sample)> columns;
};

/// A run, as a front end has translated its arguments.
struct RunPlan {
  const Scene* scene = nullptr;           ///< the run's scene: its parameter and initial values
  const runtime::Model* model = nullptr;  ///< the run's model (built for the variational step when asked)
  std::vector<double> p;                  ///< its parameter values (the model's order)
  runtime::InitialState initial;
  std::vector<double> times;  ///< the output times; under a controller its samples
  runtime::IntegratorOptions options;
  std::vector<SceneEvent> events;  ///< run_events(): [events], the stop contacts' slips, stop_when
  runtime::InputFunction inputs;   ///< u(t, y) from outside (--input series, inputs=); empty: default signals
  RunRequest request;              ///< variational, step, max_steps
  std::optional<RunControl> control;
  /// The sliding model of the scene's contact with on_slip = "slide" (sliding_contact;
  /// build_sliding_model of the run's scene), built by the front end (with its locks): required
  /// when the scene has one and the run is not variational.
  const runtime::Model* sliding_model = nullptr;
};

struct RunOutcome {
  /// The rows (in the run model's states), the event hits, the statistics, a failure.
  runtime::RunResult run;
  std::optional<double> max_discrete_constraint;  ///< the variational integrator's largest residual
  const SceneContact* slide = nullptr;            ///< the sliding contact, when the scene has one
  std::vector<SlidingSpan> sliding;               ///< when it slid
  /// The rows where the run model's hidden constraints and invariants hold (all but the sliding
  /// ones): what the drift is measured over.
  std::vector<runtime::Sample> drift_samples;
  std::vector<std::string> notes;  ///< summary lines (switches back to rolling, the drift's rows)
  long controller_calls = 0;
  /// Per row, the scene [controller]'s discrete states (its state_columns), or the values of
  /// RunControl::columns, when it ran.
  std::vector<std::vector<double>> controller_rows;
};

/// The run: the variational integrator (check_run_features has refused what it cannot carry), or
/// the hybrid IDA loop. A sliding contact starts sliding only when the rolling model cannot start
/// from the given values (its consistent point keeps every given value and solves the others,
/// as nhc analyze does); under a controller the events and the contact's switches are located
/// between the samples, and the held inputs carry over each switch. The laws of [inputs] are
/// written into the rows' inputs (record_law_inputs). A failure of the integrator ends the run
/// with the rows up to there (RunResult::failure); an exception of the controller passes through.
RunOutcome simulate(const RunPlan& plan);

/// The run of `plan` with IDAS's forward sensitivities by `thetas` (check_run_features has refused
/// what it cannot carry: a controller, an event that ends the run, a contact, replaced inputs, the
/// variational integrator), the laws of [inputs] written into its rows.
runtime::SensitivityRun simulate_sensitivities(const RunPlan& plan,
                                               const std::vector<runtime::SensitivityParameter>& thetas,
                                               const runtime::SensitivityOptions& options);

/// A file written beside the output `output` (its name side(output), e.g. events_csv_path): only
/// when `output` is a file of its own (a new name, a regular file, a link to one). None for no
/// output, standard output ("-"), or a stream (a character device or FIFO, output_target():
/// /dev/null beside which no file belongs), with `note` saying so in the last case.
std::string side_file_path(const std::string& output, const std::function<std::string(const std::string&)>& side,
                           std::string& note);

}  // namespace nhc::app
