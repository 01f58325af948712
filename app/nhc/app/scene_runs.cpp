#include "nhc/app/scene_runs.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "nhc/app/parameter_values.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/app/switched_run.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/long_work.hpp"

namespace nhc::app {

namespace {

/// The engine's run of `plan` without the symbolic lock `held` (the engine takes it for its own
/// symbolic work), which is held again when the run returns or throws. The outcome's sliding
/// scene is dropped: it belongs to the run's scene copy, which the caller releases.
RunOutcome simulate_without(std::optional<SymbolicSection>& held, const RunPlan& plan) {
  held.reset();
  struct Relock {
    std::optional<SymbolicSection>& section;
    ~Relock() { section.emplace(); }
  } relock{held};
  RunOutcome outcome = simulate(plan);
  outcome.slide = nullptr;
  return outcome;
}

}  // namespace

SceneRuns::SceneRuns(const Scene& scene, const runtime::Model& model, const runtime::Model* sliding, RunRequest request,
                     FieldNames names)
    : scene_(&scene), model_(&model), sliding_(sliding), request_(std::move(request)), names_(std::move(names)) {
  refuse_many_runs_of_mpc(scene, "these runs");
  if (sliding_contact(scene) && !sliding)
    throw std::logic_error("scene runs: the sliding model of the scene's contact is missing");
  times_ = scene.controller.present ? scene_controller_samples(request_, scene, names_)
                                    : run_output_times(request_, scene, names_);
}

SceneRun SceneRuns::run(const RunValues& values) const {
  // Symbolic work (the run's scene copied and set, its events and controller laws made, all of it
  // released) holds the symbolic lock; the engine's integration runs without it. Declared first:
  // held again while the objects below are destroyed, also when an exception passes.
  std::optional<SymbolicSection> symbolic;
  symbolic.emplace();
  auto scene = std::make_unique<Scene>(*scene_);
  set_parameter_values(*scene, values.parameters);
  // A derivative the scene gives no lower orders of starts them at 0 (x'(0) without x: x = 0).
  std::vector<InitialValue> initial;
  for (const InitialValue& v : values.initial) {
    const std::size_t primes = v.name.size() - v.name.find_last_not_of('\'') - 1;
    const std::string base = v.name.substr(0, v.name.size() - primes);
    const auto given = scene->initial.values.find(base);
    const std::size_t have = given == scene->initial.values.end() ? 0 : given->second.size();
    for (std::size_t k = have; k < primes; ++k) {
      const std::string lower = base + std::string(k, '\'');
      bool named = false;
      for (const InitialValue& w : values.initial) named = named || w.name == lower;
      if (!named) initial.push_back({lower, 0.0, v.written});
    }
    initial.push_back(v);
  }
  apply_initial_values(*scene, initial, names_.at);

  SceneRun out;
  const runtime::Model& model = *model_;
  out.p = model_parameters(model, *scene);
  RunPlan plan;
  plan.scene = scene.get();
  plan.model = &model;
  plan.p = out.p;
  plan.initial = initial_state_of(*scene, model);
  plan.times = times_;
  plan.options = run_integrator_options(request_, *scene);
  plan.events = run_events(request_, *scene, names_);
  plan.request = request_;
  plan.sliding_model = sliding_;
  if (scene->controller.present) {
    auto laws = std::make_shared<ControllerLaws>(*scene, model, out.p);
    plan.control = RunControl{sample_law(laws), laws->held(), times_, scene->controller.period, laws, {}};
  }
  out.outcome = simulate_without(symbolic, plan);
  return out;
}

void refuse_many_runs_of_mpc(const Scene& scene, const std::string& command) {
  if (!scene.controller.mpc.present) return;
  throw InputError(scene.controller.mpc.where,
                   command +
                       " does not run the scene's model predictive control (mpc): its plans are solved by IPOPT, "
                       "which nhc simulate and Python's Model.simulate load, and each run would derive its horizon "
                       "problem again; run nhc simulate --set NAME=… for each value");
}

SceneRun SceneRuns::run_at(const runtime::Model& model, const std::vector<double>& p,
                           const runtime::InitialState& initial, const std::vector<double>& times,
                           const runtime::IntegratorOptions& options) const {
  if (scene_->controller.present) throw std::logic_error("scene runs: a controller's rows are its samples");
  std::optional<SymbolicSection> symbolic;  // as in run()
  symbolic.emplace();
  auto scene = std::make_unique<Scene>(*scene_);
  std::vector<std::pair<std::string, double>> values;
  const std::map<std::string, double> now = scene->parameter_values_by_name();
  for (int k = 0; k < model.n_parameters(); ++k) {
    const std::string& name = model.table().parameter_names[k];
    const auto at = now.find(name);
    const double v = p.at(static_cast<std::size_t>(k));
    if (at != now.end() && at->second != v) values.emplace_back(name, v);
  }
  set_parameter_values(*scene, values);
  SceneRun out;
  out.p = p;
  RunPlan plan;
  plan.scene = scene.get();
  plan.model = &model;
  plan.p = p;
  plan.initial = initial;
  plan.times = times;
  plan.options = options;
  plan.events = run_events(request_, *scene, names_);
  plan.request = request_;
  plan.sliding_model = sliding_;
  out.outcome = simulate_without(symbolic, plan);
  return out;
}

std::vector<std::string> run_places_reading(const Scene& scene, const std::string& name) {
  std::vector<std::string> found;
  const std::optional<int> k = scene.jet->parameter_index(name);
  if (!k) return found;
  const GiNaC::ex symbol = scene.jet->parameter(*k);
  const auto reads = [&](const GiNaC::ex& e) { return expand_intermediates(e).has(symbol); };
  for (const SceneEvent& e : scene.events)
    if (reads(e.expression)) found.push_back("event '" + e.name + "' (" + e.where.str() + ")");
  for (const SceneContact& c : scene.contacts)
    if (reads(c.normal)) found.push_back("the normal force of contact '" + c.name + "' (" + c.where.str() + ")");
  for (const SceneControllerLaw& law : scene.controller.inputs)
    if (reads(law.expression)) found.push_back("[controller] input '" + law.name + "' (" + law.where.str() + ")");
  for (const SceneControllerLaw& law : scene.controller.update)
    if (reads(law.expression)) found.push_back("[controller] update of '" + law.name + "' (" + law.where.str() + ")");
  // A contact's mu and a controller state's start value: numbers each run evaluates again.
  const std::vector<std::string> grid = run_grid_numbers_using(scene, name);
  for (const std::string& number : experiment_numbers_using(scene, name))
    if (std::find(grid.begin(), grid.end(), number) == grid.end()) found.push_back(number);
  return found;
}

}  // namespace nhc::app
