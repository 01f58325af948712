#include "model_bindings.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "model_argument.hpp"
#include "nhc/app/parameter_values.hpp"
#include "nhc/app/initial_values.hpp"
#include "nhc/app/initial_values.hpp"
#include "nhc/app/preparation.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/app/mpc_controller.hpp"
#include "nhc/app/run_engine.hpp"
#include "nhc/app/scene_outputs.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/errors.hpp"
#include "nhc/jit.hpp"
#include "nhc/linearize.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/scene/scene.hpp"
#include "symbolic_work.hpp"

namespace py = pybind11;

namespace nhc::python {

namespace {

/// A variant of a built model generated with more functions (dF/dp: jit::BuildOptions::sensitivities;
/// the variational step: BuildOptions::variational; the multiplier-free form: reduced_form), built
/// on the first call that needs it; shared by the copies of a BuiltModel.
struct OnDemandModel {
  std::mutex building;
  std::shared_ptr<jit::LoadedModel> loaded;
};

/// A built model with the scene it came from (its initial data and names, its parameter values),
/// and the scene as written that the code was generated from: parameters are run-time values
/// (nhc/app/parameter_values.hpp), so every `set=` of one scene finds the same compiled model.
struct BuiltModel {
  Scene scene;
  Scene header_scene;
  ModelKind kind;
  std::shared_ptr<jit::LoadedModel> loaded;
  std::vector<double> parameters;  ///< the model's parameters at `scene`'s values
  std::shared_ptr<OnDemandModel> with_sensitivities = std::make_shared<OnDemandModel>();
  std::shared_ptr<OnDemandModel> with_variational_step = std::make_shared<OnDemandModel>();
  std::shared_ptr<OnDemandModel> with_reduced_form = std::make_shared<OnDemandModel>();
  /// The symbolic linearization of the model (input_jacobian, linearize_along without keep or
  /// states), made on first use; created, used and destroyed with the GIL held (GiNaC inside).
  std::shared_ptr<std::optional<Linearizer>> linearizer = std::make_shared<std::optional<Linearizer>>();
  /// runtime::csv_header(model()) as Python strings, made on first use; created, read and
  /// destroyed with the GIL held (BuiltModel lives in Python objects).
  std::shared_ptr<py::tuple> csv_columns = std::make_shared<py::tuple>();
  const runtime::Model& model() const { return loaded->model(); }
  const py::tuple& columns() const {
    if (csv_columns->empty()) *csv_columns = py::cast(runtime::csv_header(model()));
    return *csv_columns;
  }

  /// The loaded model for `thetas`: this one unless a parameter is among them and dF/dp is
  /// missing. Called with the GIL held (symbolic_work.hpp).
  const runtime::Model& model_for(const std::vector<runtime::SensitivityParameter>& thetas) const {
    const bool needs_dp = std::any_of(thetas.begin(), thetas.end(), [](const runtime::SensitivityParameter& th) {
      return th.kind == runtime::SensitivityParameter::Kind::parameter;
    });
    if (!needs_dp || model().has_parameter_jacobian()) return model();
    jit::BuildOptions options;
    options.sensitivities = true;
    return built_once(*with_sensitivities, options);
  }

  /// The model with the discrete Lagrange–d'Alembert step (simulate(integrator="variational")),
  /// built on first use. Called with the GIL held.
  const runtime::Model& variational_model() const {
    jit::BuildOptions options;
    options.variational = true;
    return built_once(*with_variational_step, options);
  }

  /// The model with the multiplier-free form's functions (BuildOptions::reduced_form: mass_matrix,
  /// forcing, velocities, speeds), built on first use. Called with the GIL held.
  const runtime::Model& reduced_form_model() const {
    jit::BuildOptions options;
    options.reduced_form = true;
    return built_once(*with_reduced_form, options);
  }

 private:
  /// The GIL serialises the builds (it is released only while one waits for the compiler, when
  /// another thread may come here: the mutex, taken without the GIL, keeps it to one build).
  const runtime::Model& built_once(OnDemandModel& slot, const jit::BuildOptions& options) const {
    std::unique_lock<std::mutex> lock(slot.building, std::try_to_lock);
    if (!lock.owns_lock()) {
      py::gil_scoped_release unlocked;
      lock.lock();
    }
    if (!slot.loaded)
      slot.loaded =
          std::make_shared<jit::LoadedModel>(symbolic_work([&] { return jit::build(header_scene, kind, options); }));
    return slot.loaded->model();
  }
};

/// `header_scene`: the scene as written (before `set=`), whose header every parameter value shares;
/// none: `scene` itself. The path of nhc simulate (app::prepare_and_build): given initial values that
/// miss a hidden constraint are refused in its words before anything is compiled, and the model
/// is derived and analysed once.
/// `backend`: "compiled", "interpreted" or "auto" (docs/interpreter.md; interpreted, the program
/// comes from the scene cache when the scene was interpreted before).
BuiltModel build(const Scene& scene, const std::string& model, const std::optional<Scene>& header_scene,
                 const std::string& backend) {
  const ModelKind kind = model_named(model);
  const Scene& written = header_scene ? *header_scene : scene;
  jit::BuildOptions options;
  const std::optional<jit::Backend> chosen = jit::parse_backend(backend);
  if (!chosen)
    throw py::value_error("backend must be \"compiled\", \"interpreted\" or \"auto\", not \"" + backend + "\"");
  options.backend = *chosen;
  auto loaded = std::make_shared<jit::LoadedModel>(symbolic_work([&] {
    app::Preparation preparation(scene, kind);
    return std::move(app::prepare_and_build(preparation, written, false, options).built);
  }));
  std::vector<double> p = app::model_parameters(loaded->model(), scene);
  return BuiltModel{scene, written, kind, std::move(loaded), std::move(p)};  // with the GIL: it holds Python objects
}

/// A Python callable as a message names it: its __qualname__, else its repr.
std::string describe(const py::handle& f) {
  if (py::hasattr(f, "__qualname__")) return py::str(f.attr("__qualname__"));
  return py::str(py::repr(f));
}

/// One run: the CSV's columns as a matrix (rows: output times) and the summary.
/// u(t, y) from a Python callable returning the model's inputs, called with the GIL held. An
/// exception in it cannot cross the integrator (C): it is kept, the inputs become NaN (so the
/// residual is not finite and the run stops), and simulate raises it afterwards.
struct PythonInputs {
  py::function f;
  int n_states = 0, n_inputs = 0;
  std::shared_ptr<std::optional<py::error_already_set>> failure =
      std::make_shared<std::optional<py::error_already_set>>();

  void operator()(double t, const double* y, double* u) const {
    py::gil_scoped_acquire locked;
    if (*failure) {
      std::fill(u, u + n_inputs, std::nan(""));
      return;
    }
    try {
      const py::array_t<double> state(n_states, y);
      const py::object returned = f(t, state);
      // numpy would read None as one NaN, and the run would stop at "residual ... is NaN".
      if (returned.is_none())
        throw py::type_error("the inputs function " + describe(f) + " returned None, not the model's " +
                             std::to_string(n_inputs) + " inputs");
      const py::array_t<double, py::array::c_style | py::array::forcecast> values(returned);
      if (values.size() != n_inputs)
        throw py::type_error("the inputs function " + describe(f) + " returned " + std::to_string(values.size()) +
                             " values, the model has " + std::to_string(n_inputs) + " inputs");
      std::copy(values.data(), values.data() + n_inputs, u);
    } catch (py::error_already_set& e) {
      failure->emplace(std::move(e));
      std::fill(u, u + n_inputs, std::nan(""));
    } catch (const py::builtin_exception& e) {
      e.set_error();  // as the Python exception it names, raised after the run
      failure->emplace();
      std::fill(u, u + n_inputs, std::nan(""));
    }
  }
};

/// Ctrl-C during a run (the GIL released): Python's handler only records the signal; every
/// kStopCheckMilliseconds the run takes the GIL and lets Python act on it (KeyboardInterrupt),
/// then stops.
struct InterruptCheck {
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  std::shared_ptr<std::optional<py::error_already_set>> raised =
      std::make_shared<std::optional<py::error_already_set>>();

  bool operator()() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(kStopCheckMilliseconds)) return false;
    last = now;
    py::gil_scoped_acquire locked;
    if (PyErr_CheckSignals() == 0) return false;
    raised->emplace();
    return true;
  }
};

/// The summary of a run (IDA's counters, the time split, the drift of the samples), built when
/// it is first read (Run.summary): a loop of runs that never reads it does not pay for it.
/// `extra` entries (the sensitivities' counters) are added to it.
py::cpp_function summary_of(const BuiltModel& built, const runtime::Model& model, std::vector<double> p,
                            const runtime::Statistics& st, std::vector<runtime::Sample> samples,
                            std::map<std::string, long> extra = {}, bool reference_applies = true) {
  struct Run {
    std::vector<double> p;
    runtime::Statistics statistics;
    std::vector<runtime::Sample> samples;
    std::map<std::string, long> extra;
  };
  auto run = std::make_shared<Run>(Run{std::move(p), st, std::move(samples), std::move(extra)});
  // The libraries that own `model` (the plain one, or the one with dF/dp) stay loaded as long as
  // the function lives; the timings are the plain build's.
  const jit::BuildTimings timings = built.loaded->timings();
  return py::cpp_function([keep = built.loaded, keep_sensitivities = built.with_sensitivities,
                           keep_variational = built.with_variational_step, timings, &model, run, reference_applies]() {
    const runtime::Statistics& st = run->statistics;
    py::dict summary;
    summary["steps"] = st.steps;
    summary["residual_evaluations"] = st.residual_evaluations;
    summary["jacobian_evaluations"] = st.jacobian_evaluations;
    summary["error_test_failures"] = st.error_test_failures;
    summary["nonlinear_failures"] = st.nonlinear_failures;
    summary["linear_solver"] = st.linear_solver;
    summary["jacobian"] = st.jacobian;
    summary["derive_seconds"] = timings.derive + timings.generate;
    summary["compile_seconds"] = timings.compile + timings.load;
    summary["integrate_seconds"] = st.initialization_seconds + st.integration_seconds;
    for (const auto& [name, value] : run->extra) summary[py::str(name)] = value;
    const runtime::DriftReport drift = runtime::measure_drift(model, run->p, run->samples);
    summary["hidden_drift"] = drift.max_hidden;
    if (reference_applies || model.n_reference() == 0) {
      summary["reference_error"] = drift.max_error;
    } else {  // the closed forms are of the scene's own start (docs/combinations.md)
      summary["reference_error"] = py::none();
      summary["reference_note"] =
          "no reference error: the closed forms of [reference] start from the scene's own "
          "[initial], and initial= or t0= moved the start";
    }
    py::dict invariant_drift;
    for (int k = 0; k < model.n_invariants(); ++k)
      invariant_drift[py::str(model.table().invariant_names[k])] = drift.invariant_drift[static_cast<std::size_t>(k)];
    summary["invariant_drift"] = invariant_drift;
    return summary;
  });
}

/// The CSV's columns (and `extra` ones, filled by `extra_values` per sample) as a matrix whose
/// rows are the output times.
py::array_t<double> data_of(const runtime::Model& model, const std::vector<double>& p,
                            const std::vector<runtime::Sample>& samples, std::size_t n_columns,
                            const std::function<void(std::size_t, std::vector<double>&)>& extra_values = {}) {
  py::array_t<double> data({static_cast<py::ssize_t>(samples.size()), static_cast<py::ssize_t>(n_columns)});
  auto rows = data.mutable_unchecked<2>();
  const runtime::CsvRows csv(model, p);
  std::vector<double> values, extra;
  for (std::size_t r = 0; r < samples.size(); ++r) {
    csv.row(samples[r], values);
    if (extra_values) extra_values(r, extra), values.insert(values.end(), extra.begin(), extra.end());
    for (std::size_t c = 0; c < values.size(); ++c)
      rows(static_cast<py::ssize_t>(r), static_cast<py::ssize_t>(c)) = values[c];
  }
  return data;
}

/// The result dict Model.simulate turns into a Run; a failure after some samples is reported in
/// it (the caller raises with the samples kept), one before any is thrown.
py::dict result_of(py::object columns, py::array_t<double> data, py::cpp_function summary,
                   const std::optional<base::SolverError>& failure) {
  py::dict out;
  out["columns"] = std::move(columns);
  out["data"] = std::move(data);
  out["summary"] = std::move(summary);
  if (failure) {
    out["failure"] = std::string(failure->what());
    out["failure_t"] = failure->t();
  }
  return out;
}

/// Output times as a message quotes them: "0, 0.5, 0.2, 1".
std::string join_numbers(const std::vector<double>& values) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + base::shortest_text(values[i]);
  return out;
}

/// simulate(sensitivity=[names]): the run with IDAS's forward sensitivities
/// (app::simulate_sensitivities); the columns are the plain ones followed by
/// d(<state>)/d(<name>) (runtime::sensitivity_csv_header).
py::dict simulate_sensitivities(const BuiltModel& built, app::RunPlan plan, const std::vector<std::string>& names,
                                InterruptCheck interrupt, bool reference_applies) {
  const Scene& scene = *plan.scene;
  const runtime::Model& plain = built.model();  // the inputs follow their default signals
  // As nhc simulate --sensitivity: a parameter only [initial] is written through among them.
  const std::vector<runtime::SensitivityParameter> thetas =
      app::sensitivity_parameters(scene, plain, names, "sensitivity");
  try {
    runtime::require_given(thetas, plan.initial);
  } catch (const std::invalid_argument& e) {
    throw InputError({"sensitivity", 0, 0}, e.what());
  }
  plan.options.stop_requested = interrupt;
  const std::vector<double>& p = built.parameters;
  runtime::SensitivityRun run;
  const runtime::Model* model = &built.model_for(thetas);  // a build: symbolic work, with the GIL
  plan.model = model;
  try {
    py::gil_scoped_release unlocked;
    run = app::simulate_sensitivities(plan, thetas, {});
  } catch (...) {  // stopped before the first sample (the initialization): still KeyboardInterrupt
    if (*interrupt.raised) throw std::move(**interrupt.raised);
    throw;
  }
  if (*interrupt.raised) throw std::move(**interrupt.raised);
  if (run.failure && run.samples.empty()) throw *run.failure;
  std::vector<std::string> columns = runtime::csv_header(*model);
  const std::vector<std::string> sensitivity_columns = runtime::sensitivity_csv_header(*model, thetas);
  columns.insert(columns.end(), sensitivity_columns.begin(), sensitivity_columns.end());
  std::vector<runtime::Sample> states;
  for (const runtime::SensitivitySample& s : run.samples) states.push_back(s.state());
  py::array_t<double> data = data_of(*model, p, states, columns.size(), [&](std::size_t r, std::vector<double>& v) {
    runtime::sensitivity_values(*model, run.samples[r], v);
  });
  return result_of(py::cast(columns), std::move(data),
                   summary_of(built, *model, p, run.statistics.state, std::move(states),
                              {{"sensitivity_residual_evaluations", run.statistics.sensitivity_residual_evaluations}},
                              reference_applies),
                   run.failure);
}

/// A Python controller f(t, y, state) -> (inputs, new_state) as the engine's sample law, called
/// with the GIL at each sample. An exception in f ends the run (kept in `failure`, raised after it).
app::SampleLaw python_controller(const py::function& f, std::shared_ptr<py::object> state, int n_states, int n_inputs,
                                 std::shared_ptr<std::optional<py::error_already_set>> failure) {
  return [f, state, failure, n_states, n_inputs](const runtime::Sample& reached) -> std::vector<double> {
    py::gil_scoped_acquire locked;
    try {
      const py::array_t<double> y(n_states, reached.y.data());
      const py::object returned = f(reached.t, y, *state);
      const py::tuple pair(returned);  // any pair: (u, state) or [u, state]
      if (pair.size() != 2) throw py::type_error("the controller " + describe(f) + " must return (inputs, new_state)");
      const py::object first = pair[0];
      const py::array_t<double, py::array::c_style | py::array::forcecast> values(first);
      if (values.size() != n_inputs)
        throw py::type_error("the controller " + describe(f) + " returned " + std::to_string(values.size()) +
                             " inputs, the model has " + std::to_string(n_inputs));
      *state = py::object(pair[1]);
      return std::vector<double>(values.data(), values.data() + n_inputs);
    } catch (py::error_already_set& e) {
      failure->emplace(std::move(e));
    } catch (const py::builtin_exception& e) {
      e.set_error();
      failure->emplace();
    }
    throw base::SolverError(base::FailureKind::stopped, reached.t, "the controller raised an exception");
  };
}

/// Model.simulate: the arguments translated into the engine's plan (app/run_engine.hpp), the one
/// run of nhc simulate's too. `controller`: None (none), True (the scene's [controller]) or
/// f(t, y, state) -> (inputs, new_state) with `period`.
py::dict simulate(const BuiltModel& built, const std::optional<double>& t_end, const std::optional<double>& rtol,
                  const std::optional<double>& atol, const std::optional<long long>& outputs,
                  const std::optional<std::vector<double>>& output_times, const std::optional<py::function>& inputs,
                  long long max_steps, const std::optional<std::vector<std::string>>& sensitivity,
                  const std::string& integrator, const std::optional<double>& step,
                  const std::optional<std::string>& stop_when,
                  const std::optional<std::vector<std::pair<std::string, double>>>& initial_values,
                  const std::optional<double>& t0_value, const py::object& controller,
                  const std::optional<double>& period, py::object controller_state,
                  const std::optional<double>& max_step, const std::optional<double>& initial_step) {
  const bool variational = integrator == "variational";
  // initial= and t0= are [initial] values written from outside, the command line's --initial rule.
  Scene scene = built.scene;
  if (t0_value) app::apply_initial_values(scene, {{"t0", *t0_value, ""}}, "t0");
  std::vector<app::InitialValue> given;
  if (initial_values)
    for (const auto& [name, value] : *initial_values)
      given.push_back({name, value, name + " = " + base::number_text(value, 17)});
  app::apply_initial_values(scene, given, "initial");
  // The closed forms of [reference] are of the scene's own start (docs/combinations.md).
  const bool reference_applies = !t0_value && (!initial_values || initial_values->empty());
  if (!variational && integrator != "ida")
    throw InputError({"integrator", 0, 0}, "integrator '" + integrator + "': ida or variational");
  const bool scene_controller =
      !controller.is_none() && py::isinstance<py::bool_>(controller) && controller.cast<bool>();
  // controller=nhc.Mpc(...): model predictive control of the scene's [optimize] problem (docs/mpc.md).
  const bool mpc_given = !controller.is_none() && py::isinstance<SceneMpc>(controller);
  const bool function_controller = !controller.is_none() && !py::isinstance<py::bool_>(controller) && !mpc_given;
  if (function_controller && !PyCallable_Check(controller.ptr()))
    throw InputError({"controller", 0, 0},
                     "controller= must be a function f(t, y, state) -> (inputs, new_state) or nhc.Mpc(...)");
  if (period && !function_controller && !mpc_given)
    throw InputError({"period", 0, 0},
                     scene_controller
                         ? "period= goes with controller=; the scene's [controller] has its own"
                         : "period= goes with controller= (a function f(t, y, state) -> (inputs, new_state))");
  if (function_controller && !period)
    throw InputError({"period", 0, 0}, "controller= needs period= (the sample period h)");
  if (mpc_given && !period && !scene.controller.present)
    throw InputError({"period", 0, 0},
                     "controller=nhc.Mpc(...) needs period= (the sample period h): the scene has no [controller]");
  if (scene_controller && !scene.controller.present)
    throw InputError({"controller", 0, 0}, "the scene has no [controller]: give controller= and period=");
  std::optional<SceneMpc> mpc;
  if (mpc_given) {
    mpc = controller.cast<SceneMpc>();
    mpc->present = true;
    mpc->where = {"controller", 0, 0};
    const double h = period.value_or(scene.controller.period);
    if (!(mpc->horizon >= h))
      throw InputError({"controller", 0, 0}, "controller=nhc.Mpc(horizon=" + base::shortest_text(mpc->horizon) +
                                                 "): the horizon is shorter than the period " + base::shortest_text(h) +
                                                 ": each plan must reach the next sample");
  } else if (scene_controller && scene.controller.mpc.present) {
    mpc = scene.controller.mpc;
  }
  // The command line's rules (nhc/app/run_request.hpp), in the arguments' names; what is not
  // given is the scene's [simulate].
  app::RunRequest request;
  request.t_end = t_end;
  request.rtol = rtol;
  request.atol = atol;
  request.outputs = outputs;
  if (output_times) {
    request.output_times = *output_times;
    request.output_times_text = "[" + join_numbers(*output_times) + "]";
  }
  request.max_steps = max_steps;
  request.variational = variational;
  request.step = step;
  request.stop_when = stop_when;
  request.max_step = max_step, request.initial_step = initial_step;  // IDA's largest and first step
  app::RunFeatures features;                                         // what the engine refuses to combine
  features.controller = scene_controller || function_controller || mpc_given;
  features.controller_name = mpc ? (mpc_given ? "model predictive control" : "the scene's model predictive control")
                             : scene_controller ? "the scene's [controller]"
                                                : "the controller";
  features.controller_where = mpc ? mpc->where.str() : scene_controller ? scene.controller.where.str() : "controller=";
  features.mpc = mpc.has_value();
  if (scene_controller && !mpc_given)
    for (const SceneControllerLaw& law : scene.controller.inputs) features.controlled_inputs.push_back(law.name);
  if (mpc)
    for (const SceneInput& input : scene.inputs)
      if (!input.feedback) features.controlled_inputs.push_back(input.name);
  features.controls_all_inputs = function_controller;
  features.inputs_function = inputs.has_value();
  features.sensitivities = sensitivity.has_value();
  features.variational = variational;
  features.outputs = outputs.has_value();
  features.output_times = output_times.has_value();
  app::check_run_features(scene, features, app::python_names());
  app::check_run_request(request, scene, built.kind, app::python_names());
  const runtime::Model& model = built.model();
  const std::vector<double>& p = built.parameters;
  std::vector<double> times;
  if (scene_controller || (mpc_given && !period))
    times = app::scene_controller_samples(request, scene, app::python_names());
  else if (function_controller || mpc_given)
    times =
        app::sample_times(scene.initial.t0, app::run_t_end(scene, t_end, "t_end"), *period, {"period", 0, 0}, "period");
  else times = app::run_output_times(request, scene, app::python_names());
  const InterruptCheck interrupt;
  app::RunPlan plan;
  plan.scene = &scene;
  plan.model = &model;
  plan.p = p;
  plan.times = times;
  plan.options = app::run_integrator_options(request, scene);
  plan.events = app::run_events(request, scene, app::python_names());
  plan.request = request;
  plan.initial = app::initial_state_of(scene, model);
  if (sensitivity) {
    if (model.n_inputs() == 0 && inputs) throw InputError({"inputs", 0, 0}, "the scene has no [inputs]");
    return simulate_sensitivities(built, std::move(plan), *sensitivity, interrupt, reference_applies);
  }
  plan.options.stop_requested = interrupt;
  std::shared_ptr<std::optional<py::error_already_set>> input_failure;
  if (inputs) {
    if (model.n_inputs() == 0) throw InputError({"inputs", 0, 0}, "the scene has no [inputs]");
    PythonInputs python_inputs{*inputs, model.n_states(), model.n_inputs()};
    input_failure = python_inputs.failure;
    plan.inputs = python_inputs;
  }
  // The controller: the scene's laws, or the Python function.
  std::shared_ptr<app::ControllerLaws> laws;
  auto controller_failure = std::make_shared<std::optional<py::error_already_set>>();
  std::shared_ptr<app::MpcController> mpc_controller;
  if (mpc) {
    // The NLP is derived and lowered here, once (symbolic work, with the GIL); the solves run in the loop.
    mpc_controller = symbolic_work([&] { return std::make_shared<app::MpcController>(scene, model, *mpc); });
    plan.control =
        app::RunControl{app::sample_law(mpc_controller),
                        mpc_controller->held(),
                        times,
                        period.value_or(scene.controller.period),
                        nullptr,
                        [mpc_controller](bool at_sample) { return mpc_controller->column_values(at_sample); }};
  } else if (scene_controller) {
    laws = symbolic_work([&] { return std::make_shared<app::ControllerLaws>(scene, model, p); });
    plan.control = app::RunControl{app::sample_law(laws), laws->held(), times, scene.controller.period, laws, {}};
  } else if (function_controller) {
    plan.control =
        app::RunControl{python_controller(controller, std::make_shared<py::object>(std::move(controller_state)),
                                          model.n_states(), model.n_inputs(), controller_failure),
                        {},
                        times,
                        *period,
                        nullptr,
                        {}};
  }
  std::map<std::string, long> extra;
  if (variational) plan.model = &built.variational_model();  // a build: symbolic work, with the GIL
  const runtime::Model& run_model = *plan.model;
  // A contact with on_slip = "slide": its sliding model, built here (with the GIL).
  std::shared_ptr<jit::LoadedModel> sliding;
  if (!variational)
    if (const SceneContact* slide = app::sliding_contact(built.scene)) {
      sliding = std::make_shared<jit::LoadedModel>(
          symbolic_work([&] { return app::build_sliding_model(built.scene, *slide, built.kind, {}); }));
      plan.sliding_model = &sliding->model();
    }
  app::RunOutcome outcome;
  try {
    py::gil_scoped_release unlocked;
    outcome = app::simulate(plan);
  } catch (...) {
    if (*interrupt.raised) throw std::move(**interrupt.raised);
    throw;
  }
  if (*controller_failure) throw std::move(**controller_failure);
  if (input_failure && *input_failure) throw std::move(**input_failure);
  if (*interrupt.raised) throw std::move(**interrupt.raised);
  runtime::RunResult& run = outcome.run;
  if (run.failure && run.samples.empty()) throw *run.failure;
  if (variational) extra["newton_iterations"] = run.statistics.nonlinear_iterations;
  if (plan.control) {
    extra["samples"] = static_cast<long>(run.samples.size());
    extra["controller_calls"] = outcome.controller_calls;
  }
  // The scene's [outputs] and [contacts] after the model's columns, as nhc simulate's CSV has them
  // (an output the model does not compute is left out; a required one is a SceneError), then the
  // controller's states.
  std::optional<app::SceneOutputs> scene_outputs;
  if (!scene.outputs.empty() || !scene.contacts.empty()) scene_outputs.emplace(scene, run_model, p);
  if (outcome.slide && scene_outputs && !outcome.sliding.empty()) {
    std::vector<std::pair<double, double>> spans;
    for (const app::SlidingSpan& s : outcome.sliding) spans.emplace_back(s.from, s.to);
    scene_outputs->contacts().set_sliding(outcome.slide->name, spans, outcome.sliding[0].from_included);
  }
  py::list names(built.columns());
  if (scene_outputs)
    for (const std::string& name : scene_outputs->names()) names.append(name);
  if (laws)
    for (const std::string& name : laws->state_columns()) names.append(name);
  if (mpc_controller)
    for (const std::string& name : app::MpcController::columns()) names.append(name);
  if (mpc_controller) {
    extra["mpc_solves"] = static_cast<long>(mpc_controller->solves().size());
    long failed = 0;
    for (const app::MpcSolve& solve : mpc_controller->solves()) failed += solve.converged ? 0 : 1;
    extra["mpc_not_converged"] = failed;
  }
  std::function<void(std::size_t, std::vector<double>&)> extra_values = [&](std::size_t r, std::vector<double>& v) {
    v.clear();
    if (scene_outputs) v = scene_outputs->evaluate(run.samples[r]);
    if ((laws || mpc_controller) && r < outcome.controller_rows.size())
      v.insert(v.end(), outcome.controller_rows[r].begin(), outcome.controller_rows[r].end());
  };
  py::array_t<double> data = data_of(run_model, p, run.samples, names.size(), extra_values);
  py::dict result = result_of(
      py::tuple(names), std::move(data),
      // a contact that slid: the drift over the samples where it rolls, as nhc simulate's
      summary_of(built, run_model, p, run.statistics, std::move(outcome.drift_samples), extra, reference_applies),
      run.failure);
  if (outcome.max_discrete_constraint) result["max_discrete_constraint"] = *outcome.max_discrete_constraint;
  if (mpc_controller) result["mpc"] = mpc_controller->summary();  // nhc simulate's line
  py::list hits;  // run.events: name, t, the state at the crossing by state name
  for (const runtime::EventHit& hit : run.events) {
    py::dict event, state;
    event["name"] = hit.name;
    event["t"] = hit.t;
    for (int i = 0; i < model.n_states(); ++i)
      state[py::str(model.state_name(i))] = hit.y.at(static_cast<std::size_t>(i));
    event["state"] = state;
    hits.append(event);
  }
  result["events"] = hits;
  return result;
}

std::vector<double> vector_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, int n,
                              const char* what) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw InputError({what, 0, 0}, std::string(what) + " must be a vector of " + std::to_string(n) + " numbers");
  return std::vector<double>(a.data(), a.data() + n);
}

std::vector<double> inputs_at(const BuiltModel& built, double t, const std::vector<double>& y,
                              const std::optional<std::vector<double>>& given);

py::array_t<double> residual(const BuiltModel& built, double t,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& y,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& yp,
                             const std::optional<std::vector<double>>& u) {
  const runtime::Model& model = built.model();
  const int n = model.n_states();
  const std::vector<double> yv = vector_of(y, n, "y"), ypv = vector_of(yp, n, "yp");
  std::vector<double> p = built.parameters;  // the generated functions read the inputs after the parameters
  p.resize(static_cast<std::size_t>(model.n_parameters()));
  const std::vector<double> values = inputs_at(built, t, yv, u);
  p.insert(p.end(), values.begin(), values.end());
  py::array_t<double> r(n);
  model.table().residual(t, yv.data(), ypv.data(), p.data(), r.mutable_data());
  return r;
}

py::array_t<double> jacobian(const BuiltModel& built, double t,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& y,
                             const py::array_t<double, py::array::c_style | py::array::forcecast>& yp, double cj) {
  const runtime::Model& model = built.model();
  const int n = model.n_states();
  const std::vector<double> yv = vector_of(y, n, "y"), ypv = vector_of(yp, n, "yp");
  runtime::InputValues inputs(model, built.parameters);
  std::vector<double> column_major(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  if (!model.dense_jacobian(t, yv.data(), ypv.data(), cj, inputs.at(t, yv.data()), column_major.data()))
    throw MathError("the model was generated without a Jacobian");
  py::array_t<double> J({n, n});
  auto out = J.mutable_unchecked<2>();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) out(i, j) = column_major[static_cast<std::size_t>(i + n * j)];
  return J;
}

/// One function of the multiplier-free form (Reduced-form additions, docs/reduced-form.md) at
/// (t, q, u): `which` is 0 (velocities: n_coordinates), 1 (mass_matrix: n_speeds x n_speeds) or 2
/// (forcing: n_speeds). The inputs are `given` or the scene's default signals at t.
py::array_t<double> reduced_function(const BuiltModel& built, int which, double t,
                                     const py::array_t<double, py::array::c_style | py::array::forcecast>& q,
                                     const py::array_t<double, py::array::c_style | py::array::forcecast>& u,
                                     const std::optional<std::vector<double>>& given) {
  const runtime::Model& model = built.reduced_form_model();
  const int n = model.n_coordinates(), k = model.n_speeds();
  if (k == 0)
    throw MathError("the " + model.model_name() + " model of " + model.scene_name() +
                    " has no multiplier-free form (docs/reduced-form.md: nhc derive --form reduced says why)");
  const std::vector<double> qv = vector_of(q, n, "q"), uv = vector_of(u, k, "u");
  std::vector<double> p = built.parameters;
  p.resize(static_cast<std::size_t>(model.n_parameters()));
  const int m = model.n_inputs();
  if (given) {
    if (given->size() != static_cast<std::size_t>(m))
      throw InputError({"inputs", 0, 0}, "inputs must be a vector of " + std::to_string(m) + " numbers (" +
                                             std::to_string(given->size()) + " given)");
    p.insert(p.end(), given->begin(), given->end());
  } else if (m > 0) {
    p.resize(p.size() + static_cast<std::size_t>(m));
    model.table().default_inputs(t, p.data(), p.data() + model.n_parameters());
  }
  const nhc_model_table& table = model.table();
  if (which == 0) {
    py::array_t<double> out(n);
    table.velocities(t, qv.data(), uv.data(), p.data(), out.mutable_data());
    return out;
  }
  if (which == 2) {
    py::array_t<double> out(k);
    table.forcing(t, qv.data(), uv.data(), p.data(), out.mutable_data());
    return out;
  }
  std::vector<double> column_major(static_cast<std::size_t>(k) * static_cast<std::size_t>(k), 0.0);
  table.mass_matrix(t, qv.data(), uv.data(), p.data(), column_major.data());
  py::array_t<double> M({k, k});
  auto view = M.mutable_unchecked<2>();
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) view(i, j) = column_major[static_cast<std::size_t>(i + k * j)];
  return M;
}

/// A Linearizer of the built model's scene with `options`: the shared one without options. Its
/// index-1 states must be the compiled model's (both come from reduce_to_index1 of one scene).
const Linearizer& linearizer_of(const BuiltModel& built, const LinearizeOptions& options,
                                std::optional<Linearizer>& own) {
  const bool plain = options.keep.empty() && options.states.empty();
  std::optional<Linearizer>& slot = plain ? *built.linearizer : own;
  if (!slot) slot.emplace(symbolic_work([&] { return Linearizer(built.scene, built.kind, options); }));
  const std::vector<std::string> names = slot->index1_states();
  for (int i = 0; i < built.model().n_states(); ++i)
    if (names.size() != static_cast<std::size_t>(built.model().n_states()) ||
        names[static_cast<std::size_t>(i)] != built.model().state_name(i))
      throw MathError("the linearization's states differ from the compiled model's (" + built.model().state_name(i) +
                      "): linearize from the scene instead");
  return *slot;
}

/// The inputs at (t, y): `given` (empty: the model's default signals at t).
std::vector<double> inputs_at(const BuiltModel& built, double t, const std::vector<double>& y,
                              const std::optional<std::vector<double>>& given) {
  const runtime::Model& model = built.model();
  if (given) {
    if (given->size() != static_cast<std::size_t>(model.n_inputs()))
      throw InputError({"u", 0, 0}, "u must be a vector of " + std::to_string(model.n_inputs()) + " numbers (" +
                                        std::to_string(given->size()) + " given)");
    return *given;
  }
  runtime::InputValues values(model, built.parameters);
  const double* p = values.at(t, y.data());
  return std::vector<double>(p + model.n_parameters(), p + model.n_parameters() + model.n_inputs());
}

py::array_t<double> matrix(const Eigen::MatrixXd& m);

/// ∂F/∂u of the index-1 residual at (t, y, y', u).
py::array_t<double> input_jacobian(const BuiltModel& built, double t,
                                   const py::array_t<double, py::array::c_style | py::array::forcecast>& y,
                                   const py::array_t<double, py::array::c_style | py::array::forcecast>& yp,
                                   const std::optional<std::vector<double>>& u) {
  const int n = built.model().n_states();
  const std::vector<double> yv = vector_of(y, n, "y"), ypv = vector_of(yp, n, "yp");
  std::optional<Linearizer> own;
  const Linearizer& lin = linearizer_of(built, {}, own);
  return matrix(lin.input_jacobian(t, yv, ypv, inputs_at(built, t, yv, u)));
}

/// A(t), B(t) at each row of (t, Y, Y') with inputs from `inputs` (u(t, y), or the default
/// signals): a dict of states, inputs, A (N × n × n) and B (N × n × m).
py::dict linearize_along(const BuiltModel& built, const std::vector<double>& times,
                         const py::array_t<double, py::array::c_style | py::array::forcecast>& Y,
                         const py::array_t<double, py::array::c_style | py::array::forcecast>& YP,
                         const std::optional<py::function>& inputs, const std::vector<std::string>& keep,
                         const std::vector<std::string>& states) {
  const runtime::Model& model = built.model();
  const auto n = static_cast<py::ssize_t>(model.n_states());
  const auto N = static_cast<py::ssize_t>(times.size());
  if (Y.ndim() != 2 || YP.ndim() != 2 || Y.shape(0) != N || YP.shape(0) != N || Y.shape(1) != n || YP.shape(1) != n)
    throw InputError({"run", 0, 0},
                     "the states must be " + std::to_string(N) + " rows of " + std::to_string(n) + " values");
  LinearizeOptions options;
  options.keep = keep;
  options.states = states;
  std::optional<Linearizer> own;
  const Linearizer& lin = linearizer_of(built, options, own);
  std::optional<py::array_t<double>> A, B;
  py::dict out;
  for (py::ssize_t r = 0; r < N; ++r) {
    const double t = times[static_cast<std::size_t>(r)];
    const std::vector<double> y(Y.data(r, 0), Y.data(r, 0) + n), yp(YP.data(r, 0), YP.data(r, 0) + n);
    std::optional<std::vector<double>> u;
    if (inputs) {
      const py::array_t<double, py::array::c_style | py::array::forcecast> values(
          (*inputs)(t, py::array_t<double>(n, y.data())));
      u = std::vector<double>(values.data(), values.data() + values.size());
    }
    Linearization at;
    try {
      at = lin.along(t, y, yp, inputs_at(built, t, y, u));
    } catch (const MathError& e) {
      throw MathError("at t = " + std::to_string(t) + ": " + e.what());
    }
    if (!A) {
      A.emplace(std::vector<py::ssize_t>{N, at.A.rows(), at.A.cols()});
      B.emplace(std::vector<py::ssize_t>{N, at.B.rows(), at.B.cols()});
      out["states"] = at.states;
      out["inputs"] = at.inputs;
    } else if (py::cast<std::vector<std::string>>(out["states"]) != at.states) {
      throw MathError("at t = " + std::to_string(t) +
                      ": the hidden constraints eliminate other states than at t = " + std::to_string(times.front()) +
                      " (" + join_names(at.states) + "): choose the states with states=[...]");
    }
    auto a = A->mutable_unchecked<3>();
    auto b = B->mutable_unchecked<3>();
    for (Eigen::Index i = 0; i < at.A.rows(); ++i) {
      for (Eigen::Index j = 0; j < at.A.cols(); ++j) a(r, i, j) = at.A(i, j);
      for (Eigen::Index j = 0; j < at.B.cols(); ++j) b(r, i, j) = at.B(i, j);
    }
  }
  if (!A) throw InputError({"run", 0, 0}, "the run has no samples");
  out["A"] = *A;
  out["B"] = *B;
  return out;
}

py::array_t<double> matrix(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) view(i, j) = m(i, j);
  return out;
}

py::dict linearization(const Linearization& lin) {
  py::dict out;
  out["states"] = lin.states;
  out["cyclic"] = lin.cyclic;
  out["kept"] = lin.kept;
  out["turn_rate"] = lin.turn_rate;
  out["A"] = matrix(lin.A);
  out["inputs"] = lin.inputs;
  out["B"] = matrix(lin.B);
  out["outputs"] = lin.outputs;
  out["C"] = matrix(lin.C);
  out["D"] = matrix(lin.D);
  out["eigenvalues"] = lin.eigenvalues;
  out["verdict"] = to_string(lin.verdict);
  out["zero_eigenvalues"] = lin.zero_eigenvalues;
  py::list families;
  for (const SteadyFamily& f : lin.families) families.append(f.description);
  out["families"] = families;
  out["point"] = lin.point;
  out["notes"] = lin.notes;
  return out;
}

std::vector<PointOverride> overrides_of(const std::map<std::string, double>& at) {
  std::vector<PointOverride> out;
  for (const auto& [name, value] : at) out.push_back({name, value});
  return out;
}

}  // namespace

void register_model(py::module_& m) {
  // nhc.Mpc: the settings of model predictive control, as `mpc = { … }` in [controller] (docs/mpc.md).
  py::class_<SceneMpc>(
      m, "Mpc",
      "Model predictive control's settings, as ``mpc = { horizon = ..., intervals = ... }`` of a scene's\n"
      "[controller] (docs/mpc.md): ``Model.simulate(controller=nhc.Mpc(horizon=1.5, intervals=15))``\n"
      "solves the scene's [optimize] problem over the receding horizon at every sample.")
      .def(
          py::init([](double horizon, long long intervals, long long max_iterations, double tolerance,
                      bool warm_start) {
            if (!(std::isfinite(horizon) && horizon > 0))
              throw InputError({"horizon", 0, 0}, "horizon must be a positive number (the prediction horizon in time)");
            if (intervals < 1 || intervals > 10000)
              throw InputError({"intervals", 0, 0},
                               "intervals must be a whole number from 1 to 10000 (the horizon's mesh)");
            if (max_iterations < 1 || max_iterations > 1000000)
              throw InputError({"max_iterations", 0, 0}, "max_iterations must be a whole number from 1 to 1000000");
            if (!(std::isfinite(tolerance) && tolerance > 0 && tolerance < 1))
              throw InputError({"tolerance", 0, 0},
                               "tolerance must be a number between 0 and 1 (IPOPT's tol of each solve)");
            SceneMpc mpc;
            mpc.present = true;
            mpc.horizon = horizon;
            mpc.intervals = static_cast<int>(intervals);
            mpc.max_iterations = static_cast<int>(max_iterations);
            mpc.tolerance = tolerance;
            mpc.warm_start = warm_start;
            return mpc;
          }),
          py::arg("horizon"), py::arg("intervals"), py::arg("max_iterations") = 100, py::arg("tolerance") = 1e-8,
          py::arg("warm_start") = true)
      .def_readonly("horizon", &SceneMpc::horizon, "The prediction horizon H in time.")
      .def_readonly("intervals", &SceneMpc::intervals, "The equal intervals of the horizon's mesh.")
      .def_readonly("max_iterations", &SceneMpc::max_iterations, "IPOPT's iteration limit per solve.")
      .def_readonly("tolerance", &SceneMpc::tolerance, "IPOPT's tol per solve.")
      .def_readonly("warm_start", &SceneMpc::warm_start, "Each solve starts from the last plan shifted by one period.")
      .def("__repr__", [](const SceneMpc& mpc) {
        return "Mpc(horizon=" + base::shortest_text(mpc.horizon) + ", intervals=" + std::to_string(mpc.intervals) +
               ", max_iterations=" + std::to_string(mpc.max_iterations) +
               ", tolerance=" + base::shortest_text(mpc.tolerance) +
               ", warm_start=" + (mpc.warm_start ? "True" : "False") + ")";
      });
  py::class_<BuiltModel>(m, "_Model")
      .def_property_readonly("state_names",
                             [](const BuiltModel& b) {
                               std::vector<std::string> names;
                               for (int i = 0; i < b.model().n_states(); ++i) names.push_back(b.model().state_name(i));
                               return names;
                             })
      .def_property_readonly("parameters",
                             [](const BuiltModel& b) {
                               std::map<std::string, double> out;
                               const std::vector<double>& p = b.parameters;
                               for (int k = 0; k < b.model().n_parameters(); ++k)
                                 out[b.model().table().parameter_names[k]] = p[static_cast<std::size_t>(k)];
                               return out;
                             })
      .def_property_readonly("model_name", [](const BuiltModel& b) { return b.model().model_name(); })
      .def("simulate", &simulate, py::arg("t_end") = std::nullopt, py::arg("rtol") = std::nullopt,
           py::arg("atol") = std::nullopt, py::arg("outputs") = std::nullopt, py::arg("output_times") = std::nullopt,
           py::arg("inputs") = std::nullopt, py::arg("max_steps") = 1000000, py::arg("sensitivity") = std::nullopt,
           py::arg("integrator") = "ida", py::arg("step") = std::nullopt, py::arg("stop_when") = std::nullopt,
           py::arg("initial") = std::nullopt, py::arg("t0") = std::nullopt, py::arg("controller") = py::none(),
           py::arg("period") = std::nullopt, py::arg("controller_state") = py::none(),
           py::arg("max_step") = std::nullopt, py::arg("initial_step") = std::nullopt)
      .def_property_readonly("has_controller", [](const BuiltModel& b) { return b.scene.controller.present; })
      .def_property_readonly("inputs",
                             [](const BuiltModel& b) {
                               std::vector<std::string> names;
                               for (int k = 0; k < b.model().n_inputs(); ++k) names.push_back(b.model().input_name(k));
                               return names;
                             })
      .def_property_readonly("differential",
                             [](const BuiltModel& b) {
                               std::vector<bool> out;
                               for (int i = 0; i < b.model().n_states(); ++i)
                                 out.push_back(b.model().is_differential(i));
                               return out;
                             })
      .def("input_jacobian", &input_jacobian, py::arg("t"), py::arg("y"), py::arg("yp"), py::arg("u") = std::nullopt)
      .def("linearize_along", &linearize_along, py::arg("t"), py::arg("y"), py::arg("yp"),
           py::arg("inputs") = std::nullopt, py::arg("keep") = std::vector<std::string>{},
           py::arg("states") = std::vector<std::string>{})
      .def("residual", &residual, py::arg("t"), py::arg("y"), py::arg("yp"), py::arg("u") = std::nullopt)
      .def("jacobian", &jacobian, py::arg("t"), py::arg("y"), py::arg("yp"), py::arg("cj"))
      .def_property_readonly("speeds",
                             [](const BuiltModel& b) {
                               std::vector<std::string> names;
                               const runtime::Model& m = b.reduced_form_model();
                               for (int k = 0; k < m.n_speeds(); ++k)
                                 names.push_back(m.variable_name(m.speed_coordinate(k)) + "'");
                               return names;
                             })
      .def_property_readonly("speed_coordinates",
                             [](const BuiltModel& b) {
                               std::vector<int> out;
                               const runtime::Model& m = b.reduced_form_model();
                               for (int k = 0; k < m.n_speeds(); ++k) out.push_back(m.speed_coordinate(k));
                               return out;
                             })
      .def_property_readonly("coordinates",
                             [](const BuiltModel& b) {
                               std::vector<std::string> names;
                               for (int j = 0; j < b.model().n_coordinates(); ++j)
                                 names.push_back(b.model().variable_name(j));
                               return names;
                             })
      .def(
          "reduced_function",
          [](const BuiltModel& b, int which, double t,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& q,
             const py::array_t<double, py::array::c_style | py::array::forcecast>& u,
             const std::optional<std::vector<double>>& inputs) { return reduced_function(b, which, t, q, u, inputs); },
          py::arg("which"), py::arg("t"), py::arg("q"), py::arg("u"), py::arg("inputs") = std::nullopt);

  m.def("_build", &build, py::arg("scene"), py::arg("model"), py::arg("header_scene") = std::nullopt,
        py::arg("backend") = "compiled");
  m.def(
      "_sweep",
      [](const Scene& scene, const std::string& model, const std::string& name, double first, double last, int count,
         const std::map<std::string, double>& at, const std::vector<std::string>& keep,
         const std::vector<std::string>& states) {
        LinearizeOptions options;
        options.keep = keep;
        options.states = states;
        const SweepResult result = symbolic_work([&] {
          const Linearizer linearizer(scene, model_named(model), options);
          return sweep(linearizer, overrides_of(at), SweepRange{name, first, last, count});
        });
        py::list points, thresholds;
        for (const SweepPoint& p : result.points) {
          py::dict point = linearization(p.linearization);
          point["value"] = p.value;
          points.append(point);
        }
        for (const VerdictChange& t : result.thresholds) {
          py::dict change;
          change["value"] = t.value;
          change["from"] = to_string(t.from);
          change["to"] = to_string(t.to);
          thresholds.append(change);
        }
        py::dict out;
        out["points"] = points;
        out["thresholds"] = thresholds;
        return out;
      },
      py::arg("scene"), py::arg("model"), py::arg("name"), py::arg("first"), py::arg("last"), py::arg("count"),
      py::arg("at"), py::arg("keep") = std::vector<std::string>{}, py::arg("states") = std::vector<std::string>{});
  m.def(
      "_linearize",
      [](const Scene& scene, const std::string& model, const std::map<std::string, double>& at,
         const std::vector<std::string>& keep, const std::vector<std::string>& states, const std::string& turn) {
        LinearizeOptions options;
        options.keep = keep;
        options.states = states;
        if (!turn.empty()) options.turn = parse_turn(turn, "turn");
        const Linearization lin =
            symbolic_work([&] { return linearize(scene, model_named(model), overrides_of(at), options); });
        return linearization(lin);
      },
      py::arg("scene"), py::arg("model"), py::arg("at"), py::arg("keep") = std::vector<std::string>{},
      py::arg("states") = std::vector<std::string>{}, py::arg("turn") = "");
}

}  // namespace nhc::python
