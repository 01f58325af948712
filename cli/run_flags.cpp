// The flags of a run (run_flags.hpp).
#include "run_flags.hpp"

#include <algorithm>

#include "commands.hpp"
#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/errors.hpp"
#include "output_selection.hpp"
#include "flag_rules.hpp"
#include "parameter_overrides.hpp"
#include "pipeline.hpp"

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
  add_set_option(sub, flags.set);
  sub->add_option("--input", flags.inputs,
                  "NAME=EXPR or NAME=@FILE.csv: replace the default signal of the scene's input NAME by an "
                  "expression of t and the parameters, or a time series (columns t and NAME, linear "
                  "interpolation; repeatable)");
  add_expand_flag(sub, flags.read);
  add_work_limit_flag(sub);
  sub->add_flag("--project", flags.project, "project onto the hidden constraints (docs/projection.md)");
  sub->add_flag("--repair-initial", flags.repair,
                "move given initial values that miss a hidden constraint to the nearest consistent point");
  CLI::Option* outputs = sub->add_option("--outputs", flags.outputs,
                                         "number of output intervals (default: [simulate] outputs, else 200)")
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
}

void check_run_flags(const RunFlags& flags, const Scene& scene, ModelKind kind) {
  // Finite, and the tolerances positive and within reach: the flags' own rules (flag_rules.hpp).
  if (flags.t_end && !(*flags.t_end > scene.initial.t0))
    throw InputError({flags.scene_path, 0, 0}, "--t-end " + format_number(*flags.t_end, 17) + " must be after t0 = " +
                                                   format_number(scene.initial.t0, 17));
  const SourceLocation here{flags.scene_path, 0, 0};
  if (!variational_integrator(flags)) {
    if (flags.step) throw InputError(here, "--step is the fixed step of --integrator variational; IDA chooses its own");
    return;
  }
  if (!flags.step) throw InputError(here, "--integrator variational needs --step H (the fixed step)");
  if (flags.project)
    throw InputError(here, "--project applies to IDA: the variational integrator solves the discrete constraints "
                           "at every step");
  require_variational_scene(scene, kind);
  const double t_end = run_output_times(flags, scene).back();
  const long steps = runtime::variational_steps_needed(scene.initial.t0, t_end, *flags.step);
  if (steps < 0 || steps > flags.max_steps)
    throw InputError(here, "--step " + format_number(*flags.step, 6) + " takes " +
                               (steps < 0 ? std::string("too many") : std::to_string(steps)) + " steps to t = " +
                               format_number(t_end, 6) + ", more than --max-steps " + std::to_string(flags.max_steps));
}

FlaggedRun run_with_flags(const RunFlags& flags, const runtime::Model& model, const std::vector<double>& p,
                          const runtime::InitialState& initial, const std::vector<double>& times,
                          const runtime::IntegratorOptions& io, const runtime::InputFunction& inputs) {
  FlaggedRun out;
  if (!variational_integrator(flags)) {
    out.run = runtime::simulate(model, p, initial, times, io, {}, inputs);
    return out;
  }
  const runtime::VariationalOptions vo = runtime::variational_options(*flags.step, flags.max_steps, io);
  runtime::VariationalRun run = runtime::simulate_variational(model, p, initial, times, vo, inputs);
  out.run = std::move(run.run);
  out.max_discrete_constraint = run.max_discrete_constraint;
  return out;
}

std::vector<double> run_output_times(const RunFlags& flags, const Scene& scene) {
  const double t0 = scene.initial.t0;
  if (!flags.output_times.empty()) return parse_output_times(flags.output_times, t0);
  return flag_rules::output_times(t0, flags.t_end.value_or(scene.simulate.t_end),
                                  flags.outputs.value_or(scene.simulate.outputs.value_or(200)), "--t-end/--outputs");
}

runtime::IntegratorOptions run_integrator_options(const RunFlags& flags, const Scene& scene) {
  runtime::IntegratorOptions io;
  io.rtol = flags.rtol.value_or(scene.simulate.rtol);
  io.atol = flags.atol.value_or(scene.simulate.atol);
  io.projection = flags.project ? runtime::ProjectionMethod::in_place : runtime::ProjectionMethod::none;
  io.max_steps = flags.max_steps;
  return io;
}

runtime::InitialState run_initial_state(const RunFlags& flags, const Scene& scene_set, const runtime::Model& model) {
  runtime::InitialState initial = initial_state_of(scene_set, model);  // [initial] expressions follow --set
  if (flags.repair)  // every value may move but those pinned by [initial] fixed
    for (int i = 0; i < model.n_states(); ++i)
      initial.given[static_cast<std::size_t>(i)] =
          std::find(scene_set.initial.fixed.begin(), scene_set.initial.fixed.end(), model.state_name(i)) !=
          scene_set.initial.fixed.end();
  return initial;
}

}  // namespace nhc::cli
