// The flags of a run (run_flags.hpp).
#include "run_flags.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>

#include "commands.hpp"
#include "nhc/app/initial_values.hpp"
#include "nhc/app/input_laws.hpp"
#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/errors.hpp"
#include "nhc/app/output_selection.hpp"
#include "flag_rules.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/app/initial_values.hpp"

namespace nhc::cli {

void add_run_flags(CLI::App* sub, RunFlags& flags) {
  sub->add_option("SCENE", flags.scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", flags.model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--t-end", flags.t_end, "final time (default: [simulate] t_end)")->check(flag_rules::finite());
  sub->add_option("--rtol", flags.rtol, "relative tolerance (default: [simulate] rtol)")
      ->check(flag_rules::relative_tolerance());
  sub->add_option("--atol", flags.atol, "absolute tolerance (default: [simulate] atol)")
      ->check(flag_rules::absolute_tolerance());
  sub->add_option("--max-steps", flags.max_steps, "limit on the internal steps of the run (default 1000000)")
      ->check(flag_rules::count(1, 1000000000000LL));
  sub->add_option("--max-step", flags.max_step,
                  "IDA's largest step (default: none; the events are checked between the steps' ends too)")
      ->check(flag_rules::positive());
  sub->add_option("--initial-step", flags.initial_step,
                  "IDA's first step (default: from the problem's scale: the first output time, the tolerances "
                  "and the rates)")
      ->check(flag_rules::positive());
  add_set_option(sub, flags.set);
  sub->add_option("--input", flags.inputs,
                  "NAME=EXPR or NAME=@FILE.csv: replace the default signal of the scene's input NAME by an "
                  "expression of t and the parameters, a feedback law of the coordinates and their first "
                  "derivatives (compiled into the equations), or a time series (columns t and NAME, linear "
                  "interpolation; repeatable)");
  add_initial_flag(sub, flags.initial);
  add_expand_flag(sub, flags.read);
  add_work_limit_flag(sub);
  sub->add_flag("--project", flags.project, "project onto the hidden constraints (docs/projection.md)");
  sub->add_flag("--repair-initial", flags.repair,
                "move given initial values that miss a hidden constraint to the nearest consistent point");
  CLI::Option* outputs =
      sub->add_option("--outputs", flags.outputs, "number of output intervals (default: [simulate] outputs, else 200)")
          ->check(flag_rules::count(1, flag_rules::kMaxOutputs));
  sub->add_option("--output-times", flags.output_times,
                  "START:STEP:END or T1,T2,...: the output times (the last is the end of the run)")
      ->excludes(outputs)
      ->excludes("--t-end");
  sub->add_option("--integrator", flags.integrator,
                  "ida (BDF, adaptive; the default) or variational (discrete Lagrange-d'Alembert, fixed --step; "
                  "docs/variational.md)")
      ->check(CLI::IsMember({"ida", "variational"}));
  sub->add_option("--step", flags.step, "the fixed step of --integrator variational")->check(flag_rules::positive());
  sub->add_option("--stop-when", flags.stop_when,
                  "EXPR: end the run where the expression (of t, the coordinates, their derivatives and the "
                  "multipliers) crosses zero, located by IDA's root finding (docs/scenes.md, [events])");
  sub->add_option("--backend", flags.backend,
                  "compiled (the C++ compiler, cached), interpreted (no compiler) or auto (the default, or "
                  "$NHC_BACKEND: compiled when this model was compiled before, else interpreted and compiled "
                  "behind a long run; docs/interpreter.md)")
      ->check(CLI::IsMember({"compiled", "interpreted", "auto"}));
}

void add_initial_flag(CLI::App* sub, std::vector<std::string>& assignments) {
  sub->add_option("--initial", assignments,
                  "NAME=VALUE: an [initial] value from outside the scene, as if written there: a coordinate or "
                  "multiplier (x), a derivative (x') or t0 (repeatable; the consistent initial point is found "
                  "as for the scene's own values)");
}

void apply_initial_flags(Scene& scene, const std::vector<std::string>& assignments) {
  const std::string flag = "--initial";
  std::vector<app::InitialValue> values;
  for (const std::string& text : assignments) {
    // The message names the flag once (its location) and quotes the assignment as written.
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
      throw InputError({flag, 0, 0}, text + ": expected NAME=VALUE");
    const std::string value = text.substr(eq + 1);
    std::size_t used = 0;
    double number = 0;
    try {
      number = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size()) throw InputError({flag, 0, 0}, text + ": '" + value + "' is not a number");
    values.push_back({text.substr(0, eq), number, text});  // a value that is not finite: the rule's to refuse
  }
  app::apply_initial_values(scene, values, flag);
}

jit::Backend run_backend(const RunFlags& flags) {
  if (!flags.backend.empty()) return jit::parse_backend(flags.backend).value_or(jit::Backend::automatic);
  // $NHC_BACKEND sets the default (as NHC_CXX the compiler); an unknown value is a bad setting.
  const char* setting = std::getenv("NHC_BACKEND");
  if (!setting || !*setting) return jit::Backend::automatic;
  if (const std::optional<jit::Backend> backend = jit::parse_backend(setting)) return *backend;
  throw InputError({"NHC_BACKEND", 0, 0},
                   std::string("'") + setting + "' is not a backend: compiled, interpreted or auto");
}

namespace {

/// The command line's names for a run request's fields; the checks against the scene are located
/// at the scene file.
app::FieldNames field_names(const RunFlags& flags) {
  app::FieldNames names = app::command_line_names();
  names.at = flags.scene_path;
  return names;
}

}  // namespace

Scene load_run_scene(RunFlags& flags) {
  Scene scene = load_scene(flags.scene_path, flags.read);
  // --input NAME=EXPR of the coordinates: a feedback law, read as if written in [inputs] (the
  // scene read again); the signals of t stay --input's.
  std::map<std::string, std::string> laws;
  std::vector<std::string> signals;
  for (const std::string& text : flags.inputs) {
    const auto [name, value] = app::split_assignment("--input", text);
    if (value.rfind('@', 0) != 0 && app::is_feedback_law(scene, name, value, "--input")) laws[name] = value;
    else signals.push_back(text);
  }
  flags.inputs = signals;
  scene = app::scene_with_input_laws(scene, laws, flags.read, "--input");
  apply_initial_flags(scene, flags.initial);
  flags.request = run_request(flags);  // once; checked against the run's t0 by check_run_flags
  return scene;
}

app::RunRequest run_request(const RunFlags& flags) {
  app::RunRequest r;
  r.t_end = flags.t_end;
  r.rtol = flags.rtol;
  r.atol = flags.atol;
  if (flags.outputs) r.outputs = *flags.outputs;
  if (!flags.output_times.empty()) {
    r.output_times = app::parse_output_times(flags.output_times);
    r.output_times_text = flags.output_times;
  }
  r.max_steps = flags.max_steps;
  r.variational = variational_integrator(flags);
  r.step = flags.step;
  r.project = flags.project;
  r.stop_when = flags.stop_when;
  r.max_step = flags.max_step;
  r.initial_step = flags.initial_step;
  return r;
}

void check_run_flags(const RunFlags& flags, const Scene& scene, ModelKind kind) {
  app::check_run_request(flags.request, scene, kind, field_names(flags));
}

MpcFactory mpc_factory = nullptr;

void check_run_features(const RunFlags& flags, const Scene& scene, bool sensitivities) {
  app::RunFeatures features;
  features.controller = scene.controller.present;
  features.controller_name =
      scene.controller.mpc.present ? "the scene's model predictive control" : "the scene's [controller]";
  features.controller_where =
      scene.controller.mpc.present ? scene.controller.mpc.where.str() : scene.controller.where.str();
  features.mpc = scene.controller.mpc.present;
  for (const SceneControllerLaw& law : scene.controller.inputs) features.controlled_inputs.push_back(law.name);
  if (features.mpc)
    for (const SceneInput& input : scene.inputs)
      if (!input.feedback) features.controlled_inputs.push_back(input.name);
  for (const std::string& assignment : flags.inputs)
    features.replaced_inputs.push_back(assignment.substr(0, assignment.find('=')));
  features.sensitivities = sensitivities;
  features.variational = variational_integrator(flags);
  features.outputs = flags.outputs.has_value();
  features.output_times = !flags.output_times.empty();
  app::check_run_features(scene, features, field_names(flags));
}

std::vector<double> run_times(const RunFlags& flags, const Scene& scene) {
  if (scene.controller.present) return app::scene_controller_samples(flags.request, scene, field_names(flags));
  return run_output_times(flags, scene);
}

app::RunPlan run_plan(const RunFlags& flags, const Scene& scene_set, ModelKind kind,
                      const jit::BuildOptions& build_options, const runtime::Model& model, const std::vector<double>& p,
                      const std::vector<double>& times, runtime::IntegratorOptions io,
                      const runtime::InputFunction& inputs, std::shared_ptr<app::ControllerLaws> controller,
                      std::optional<jit::LoadedModel>& sliding) {
  app::RunPlan plan;
  plan.scene = &scene_set;
  plan.model = &model;
  plan.p = p;
  plan.initial = run_initial_state(flags, scene_set, model);
  plan.times = times;
  plan.options = std::move(io);
  plan.events = run_events(flags, scene_set);  // a contact's mu follows --set
  plan.inputs = inputs;
  plan.request = flags.request;
  if (controller)
    plan.control = app::RunControl{app::sample_law(controller), controller->held(), times,
                                   scene_set.controller.period, controller,         {}};
  if (!plan.request.variational)
    if (const SceneContact* slide = app::sliding_contact(scene_set)) {
      sliding.emplace(app::build_sliding_model(scene_set, *slide, kind, build_options));
      plan.sliding_model = &sliding->model();
    }
  return plan;
}

std::vector<SceneEvent> run_events(const RunFlags& flags, const Scene& scene) {
  return app::run_events(flags.request, scene, field_names(flags));
}

std::vector<double> run_output_times(const RunFlags& flags, const Scene& scene) {
  return app::run_output_times(flags.request, scene, field_names(flags));
}

runtime::IntegratorOptions run_integrator_options(const RunFlags& flags, const Scene& scene) {
  return app::run_integrator_options(flags.request, scene);
}

runtime::InitialState run_initial_state(const RunFlags& flags, const Scene& scene_set, const runtime::Model& model) {
  runtime::InitialState initial = app::initial_state_of(scene_set, model);  // [initial] expressions follow --set
  // --repair-initial: given values that miss a hidden constraint may move, all but those pinned by
  // [initial] fixed; consistent ones stay (base::solve_or_repair_initial_point).
  initial.repair = flags.repair;
  initial.pinned.assign(static_cast<std::size_t>(model.n_states()), false);
  for (int i = 0; i < model.n_states(); ++i)
    initial.pinned[static_cast<std::size_t>(i)] =
        std::find(scene_set.initial.fixed.begin(), scene_set.initial.fixed.end(), model.state_name(i)) !=
        scene_set.initial.fixed.end();
  return initial;
}

}  // namespace nhc::cli
