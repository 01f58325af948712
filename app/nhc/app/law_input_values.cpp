#include "nhc/app/law_input_values.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include "nhc/app/sample_expressions.hpp"

namespace nhc::app {

void record_law_inputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                       std::vector<runtime::Sample>& samples) {
  std::vector<std::pair<int, int>> laws;  // (model input index, expression index or -1: not computed)
  std::optional<SampleExpressions> expressions;
  for (const SceneInput& input : scene.inputs) {
    if (!input.feedback) continue;
    int k = -1;
    for (int i = 0; i < model.n_inputs(); ++i)
      if (model.input_name(i) == input.name) k = i;
    if (k < 0) continue;
    if (!expressions) expressions.emplace(scene, model, p);
    const bool added = expressions->add(input.law).empty();
    laws.emplace_back(k, added ? static_cast<int>(expressions->size()) - 1 : -1);
  }
  if (laws.empty()) return;
  for (runtime::Sample& s : samples) {
    if (static_cast<int>(s.u.size()) != model.n_inputs()) continue;
    const std::vector<double> values = expressions->evaluate(s);
    for (const auto& [k, e] : laws)
      s.u[static_cast<std::size_t>(k)] = e >= 0 ? values[static_cast<std::size_t>(e)] : NAN;
  }
}

void record_law_inputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                       std::vector<runtime::SensitivitySample>& samples) {
  std::vector<runtime::Sample> states;
  states.reserve(samples.size());
  for (const runtime::SensitivitySample& s : samples) states.push_back(s.state());
  record_law_inputs(scene, model, p, states);
  for (std::size_t r = 0; r < samples.size(); ++r) samples[r].u = std::move(states[r].u);
}

}  // namespace nhc::app
