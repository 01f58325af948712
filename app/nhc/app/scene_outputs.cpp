#include "nhc/app/scene_outputs.hpp"

#include <cmath>
#include <set>

#include "nhc/errors.hpp"

namespace nhc::app {

SceneOutputs::SceneOutputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : expressions_(scene, model, p), contacts_(scene, model, p) {
  const auto left_out = [&](const SceneQuantity& q, const std::string& what, const std::string& missing) {
    const std::string why = "uses " + missing + ", which the " + model.model_name() + " model does not compute";
    if (q.required) throw InputError(q.where, what + " '" + q.name + "' " + why);
    notes_.push_back("note: " + what + " '" + q.name + "' is left out of the " + model.model_name() +
                     " model's CSV: it " + why);
  };
  for (const SceneOutput& output : scene.outputs) {
    if (const std::string missing = expressions_.add(output.expression); !missing.empty()) {
      left_out(output, "output", missing);
      continue;
    }
    names_.push_back(output.name);
  }
  // The header holds the invariants the model computes (emit's invariants_in_states, which
  // refuses a required one); the others are named here with the reason.
  for (const SceneQuantity& invariant : scene.invariants) {
    bool computed = false;
    for (int k = 0; k < model.n_invariants(); ++k)
      computed = computed || invariant.name == model.table().invariant_names[k];
    if (computed) continue;
    const std::string missing = expressions_.missing(invariant.expression);
    left_out(invariant, "invariant", missing.empty() ? "a quantity" : missing);
  }
  names_.insert(names_.end(), contacts_.names().begin(), contacts_.names().end());
  notes_.insert(notes_.end(), contacts_.notes().begin(), contacts_.notes().end());
}

std::vector<double> SceneOutputs::evaluate(const runtime::Sample& sample) const {
  std::vector<double> values = expressions_.evaluate(sample);
  const std::vector<double> forces = contacts_.evaluate(sample);
  values.insert(values.end(), forces.begin(), forces.end());
  return values;
}

}  // namespace nhc::app
