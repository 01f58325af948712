#pragma once
/// \file run_flags.hpp
/// \brief The flags of a run shared by `nhc simulate` and `nhc animate`: the scene, the model,
/// the time span and outputs, the tolerances, parameter and input overrides.

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nhc/app/run_engine.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/jit/build.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

struct RunFlags {
  std::string scene_path;
  std::string model;
  std::optional<double> t_end, rtol, atol;
  std::optional<double> max_step, initial_step;  ///< --max-step, --initial-step: IDA's largest and first step
  bool project = false, repair = false;
  long max_steps = 1000000;
  std::optional<int> outputs;
  std::string output_times;
  std::vector<std::string> set;
  std::vector<std::string> inputs;       ///< --input NAME=EXPR | NAME=@FILE.csv
  std::vector<std::string> initial;      ///< --initial NAME=VALUE: [initial] values (x, x', t0) from outside
  std::string integrator = "ida";        ///< --integrator ida | variational
  std::optional<double> step;            ///< --step H of the variational integrator
  std::optional<std::string> stop_when;  ///< --stop-when EXPR: an event that ends the run
  std::string backend;                   ///< --backend compiled | interpreted | auto; empty: $NHC_BACKEND, else auto
  SceneOptions read;
  /// The flags as the application layer's run request (--output-times read against the scene's t0,
  /// not yet checked): built once, by load_run_scene, and read by every helper below.
  app::RunRequest request;
};

/// The scene of SCENE (with --expand), with the --input feedback laws (expressions of the
/// coordinates, app::input_laws.hpp) written into its [inputs] and taken out of `flags.inputs`,
/// and the --initial values written into its [initial] (app::apply_initial_values); sets
/// `flags.request` (run_request).
Scene load_run_scene(RunFlags& flags);

/// Registers --initial NAME=VALUE (repeatable) on `sub`: every command that runs the model has it.
void add_initial_flag(CLI::App* sub, std::vector<std::string>& assignments);
/// The --initial assignments written into the scene's [initial] as app::apply_initial_values
/// rules (Python's initial= and t0= follow the same rule). InputError at --initial.
void apply_initial_flags(Scene& scene, const std::vector<std::string>& assignments);

/// Registers SCENE, --model, --t-end, --rtol, --atol, --max-steps, --set, --input, --initial, --expand,
/// --project, --repair-initial, --outputs, --output-times, --integrator, --step and --stop-when on `sub`.
void add_run_flags(CLI::App* sub, RunFlags& flags);

/// The flags as the application layer's run request (--output-times read; checked against the
/// scene the run takes, its parameters set, by check_run_flags).
app::RunRequest run_request(const RunFlags& flags);

/// The flags that override [simulate], against the scene: --t-end after t0; --integrator
/// variational with --step, the chetaev model, no --project, and a step count within --max-steps.
void check_run_flags(const RunFlags& flags, const Scene& scene, ModelKind kind);

/// --integrator variational.
inline bool variational_integrator(const RunFlags& flags) { return flags.integrator == "variational"; }
/// The jit backend --backend names.
jit::Backend run_backend(const RunFlags& flags);

/// The engine's refusals (app::check_run_features) for the flags on `scene` (after load_run_scene:
/// `flags.inputs` holds the replaced signals), with `sensitivities` asked for: before anything is built.
void check_run_features(const RunFlags& flags, const Scene& scene, bool sensitivities);

/// Model predictive control (the scene's `mpc` in [controller], app/mpc_controller.hpp) as the
/// run engine takes it: the control of the run (its law, held inputs, samples, the columns
/// mpc:cost …) and the summary line after the run. Only programs that link IPOPT make it
/// (nhc-optimize sets mpc_factory); nhc-main starts nhc-optimize for a scene with mpc.
struct MpcParts {
  app::RunControl control;
  std::vector<std::string> columns;
  std::function<std::string()> summary;
};
using MpcFactory = MpcParts (*)(const Scene& scene_set, const runtime::Model& model,
                                const std::vector<double>& samples);
extern MpcFactory mpc_factory;

/// The output times: the scene [controller]'s samples when it has one, else run_output_times.
std::vector<double> run_times(const RunFlags& flags, const Scene& scene);

/// The run the flags ask for, as the engine's plan (app/run_engine.hpp), on `model` with the
/// parameter values `p` of `scene_set` (the scene after --set): the output times (run_times), the
/// events, the inputs `inputs`, the scene's controller `controller` (null: none), and the sliding
/// model of a contact that slides, built into `sliding` as `kind` with `build_options`.
app::RunPlan run_plan(const RunFlags& flags, const Scene& scene_set, ModelKind kind,
                      const jit::BuildOptions& build_options, const runtime::Model& model, const std::vector<double>& p,
                      const std::vector<double>& times, runtime::IntegratorOptions io,
                      const runtime::InputFunction& inputs, std::shared_ptr<app::ControllerLaws> controller,
                      std::optional<jit::LoadedModel>& sliding);

/// The run's events: the scene's [events] and --stop-when (app::run_events).
std::vector<SceneEvent> run_events(const RunFlags& flags, const Scene& scene);

/// The output times: --output-times, else t0 to --t-end ([simulate] t_end) in --outputs
/// ([simulate] outputs, else 200) intervals. InputError naming the flag for a bad one.
std::vector<double> run_output_times(const RunFlags& flags, const Scene& scene);

/// IDA's options: the tolerances of the flags, else of [simulate]; --project, --max-steps.
runtime::IntegratorOptions run_integrator_options(const RunFlags& flags, const Scene& scene);

/// The initial state from [initial] of `scene_set` (the scene after --set); with
/// --repair-initial every value may move but those [initial] fixed pins.
runtime::InitialState run_initial_state(const RunFlags& flags, const Scene& scene_set, const runtime::Model& model);

}  // namespace nhc::cli
