#include "nhc/app/sampled_run.hpp"

#include <algorithm>
#include <cmath>

#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::app {

std::vector<double> sample_times(double t0, double t_end, double period, const SourceLocation& where,
                                 const std::string& what) {
  const std::string shown = what + " " + base::shortest_text(period);
  if (!(std::isfinite(period) && period > 0))
    throw InputError(where, shown + ": the sample period must be a positive number");
  // The samples are t0 + k h; the run ends at the last one at or before t_end (1e-9 of a period
  // spares a t_end that is a whole number of periods written in decimals).
  const double count = std::floor((t_end - t0) / period + 1e-9);
  if (!(count >= 1))
    throw InputError(where, shown + ": the run from t0 = " + base::shortest_text(t0) +
                                " to t_end = " + base::shortest_text(t_end) + " is shorter than one period");
  if (count > static_cast<double>(kMaxOutputs))
    throw InputError(where, shown + ": more than " + std::to_string(kMaxOutputs) + " samples up to t_end");
  std::vector<double> times;
  const long n = static_cast<long>(count);
  for (long k = 0; k <= n; ++k) times.push_back(t0 + static_cast<double>(k) * period);
  if (const std::optional<std::size_t> i = runtime::collapsed_output_time(times))
    throw InputError(where, shown + ": samples " + std::to_string(*i - 1) + " and " + std::to_string(*i) +
                                " fall on the same double at t = " + base::shortest_text(times[*i]));
  return times;
}

std::vector<double> scene_controller_samples(const RunRequest& request, const Scene& scene, const FieldNames& names) {
  const SceneController& controller = scene.controller;
  const std::string why = ": the scene's [controller] runs from sample to sample, whose times are the rows (" +
                          controller.where.str() + ")";
  if (request.outputs) throw InputError({names.outputs, 0, 0}, names.outputs + why);
  if (request.output_times) throw InputError({names.output_times, 0, 0}, names.output_times + why);
  if (request.variational) throw InputError({names.variational, 0, 0}, names.variational + why);
  const double t0 = scene.initial.t0;
  return sample_times(t0, request.t_end.value_or(scene.simulate.t_end), controller.period, controller.period_where,
                      "period");
}

void refuse_scene_controller(const Scene& scene, const std::string& command) {
  if (!scene.controller.present) return;
  throw InputError(scene.controller.where,
                   command +
                       " does not run the scene's [controller] (a sampled controller): "
                       "nhc simulate and Python's Model.simulate do; without the table it runs open loop");
}

ControllerLaws::ControllerLaws(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : scene_(&scene), model_(&model), p_(p), expressions_(scene, model, p, [&scene] {
        std::vector<GiNaC::ex> symbols;
        for (const SceneControllerState& s : scene.controller.states) symbols.push_back(s.symbol);
        return symbols;
      }()) {
  const SceneController& controller = scene.controller;
  // Model predictive control is no law to evaluate: only the runs that build its solver run it.
  if (controller.mpc.present)
    throw InputError(controller.mpc.where,
                     "the scene's [controller] is model predictive control (mpc), which nhc simulate "
                     "and Python's Model.simulate run; this command does not (it would run open loop)");
  const JetSpace& jet = *scene.jet;
  held_.assign(static_cast<std::size_t>(model.n_inputs()), false);
  auto add = [&](const nhc::SceneControllerLaw& law, const std::string& what) {
    // Only what the run's states hold: an acceleration follows from the inputs being set.
    const GiNaC::ex e = expand_intermediates(law.expression);
    for (const JetCoordinate& c : jet.jet_coordinates_in(e)) {
      const int variable = c.kind == VariableKind::coordinate ? c.index : model.n_coordinates() + c.index;
      if (c.kind != VariableKind::coordinate || model.state_index(variable, c.order) < 0)
        throw InputError(law.where, what + " \"" + law.text + "\" uses " +
                                        base::primed_name(jet.variable_name(c.kind, c.index), c.order) +
                                        ", which the " +
                                        "model's states do not hold (a controller reads the state the "
                                        "run reached: coordinates and the derivatives that are states)");
    }
    if (std::string missing = expressions_.add(e); !missing.empty())
      throw InputError(law.where,
                       what + " \"" + law.text + "\" uses " + missing + ", which the model does not compute");
  };
  for (const nhc::SceneControllerLaw& law : controller.inputs) {
    const int i = model.input_index(law.name);
    if (i < 0) throw InputError(law.where, "[controller] sets input '" + law.name + "', which the model does not read");
    add(law, "controller input '" + law.name + "'");
    input_slots_.push_back(i);
    held_[static_cast<std::size_t>(i)] = true;
  }
  for (const nhc::SceneControllerLaw& law : controller.update) add(law, "update of '" + law.name + "'");
  for (const SceneControllerState& s : controller.states) {
    z_.push_back(s.initial);
    columns_.push_back("controller:" + s.name);
  }
  expressions_.prepare();
}

std::vector<double> ControllerLaws::operator()(const runtime::Sample& reached) {
  history_.push_back(z_);
  const std::vector<double> values = expressions_.evaluate(reached, z_);
  std::vector<double> u = reached.u;  // the inputs it does not set are not held (RunControl::held)
  const std::size_t n_laws = input_slots_.size();
  for (std::size_t k = 0; k < n_laws; ++k) u.at(static_cast<std::size_t>(input_slots_[k])) = values[k];
  for (std::size_t k = 0; k < z_.size(); ++k) z_[k] = values[n_laws + k];
  return u;
}

SampleLaw sample_law(std::shared_ptr<ControllerLaws> law) {
  return [law](const runtime::Sample& reached) { return (*law)(reached); };
}

}  // namespace nhc::app
