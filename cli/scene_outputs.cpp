#include "scene_outputs.hpp"

#include <cmath>
#include <set>

#include "nhc/errors.hpp"

namespace nhc::cli {

namespace {

std::string primed(const std::string& variable, int order) {
  return variable + std::string(static_cast<std::size_t>(order), '\'');
}

/// Where a jet symbol's value is found in a sample: y[index] or y'[index].
struct Located {
  JetCoordinate coordinate;
  bool derivative;
  int index;
};

/// Finds every jet symbol of `e` in the model's samples: the state holding it, else the
/// derivative y' of the state one order below. Returns the first one the model does not
/// compute, in scene notation ("" when all are found).
std::string locate(const JetSpace& jet, const GiNaC::ex& e, const runtime::Model& model, std::vector<Located>& found) {
  for (const JetCoordinate& c : jet.jet_coordinates_in(e)) {
    const int variable = c.kind == VariableKind::coordinate ? c.index : model.n_coordinates() + c.index;
    const bool known = c.kind == VariableKind::coordinate || c.index < model.n_multipliers();
    const int state = known ? model.state_index(variable, c.order) : -1;
    const int below = known && c.order > 0 ? model.state_index(variable, c.order - 1) : -1;
    if (state >= 0)
      found.push_back({c, false, state});
    else if (below >= 0 && model.is_differential(below))
      found.push_back({c, true, below});
    else
      return primed(jet.variable_name(c.kind, c.index), c.order) +
             (known ? "" : " (it has no multiplier " + jet.variable_name(c.kind, c.index) + ")");
  }
  return "";
}

}  // namespace

SceneOutputs::SceneOutputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : time_(scene.jet->time()) {
  const JetSpace& jet = *scene.jet;
  GiNaC::exmap parameters;
  // The model's values, and the scene's for a parameter only the outputs use (it is not in the
  // header; --set has given it to the scene).
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k) {
    const int i = model.parameter_index(jet.parameters()[static_cast<std::size_t>(k)]);
    parameters[jet.parameter(k)] = i >= 0 ? p.at(static_cast<std::size_t>(i)) : scene.parameter_values.at(static_cast<std::size_t>(k));
  }
  const auto left_out = [&](const SceneQuantity& q, const std::string& what, const std::string& missing) {
    const std::string why = "uses " + missing + ", which the " + model.model_name() + " model does not compute";
    if (q.required) throw InputError(q.where, what + " '" + q.name + "' " + why);
    notes_.push_back("note: " + what + " '" + q.name + "' is left out of the " + model.model_name() +
                     " model's CSV: it " + why);
  };
  std::set<JetCoordinate> bound;
  for (const SceneOutput& output : scene.outputs) {
    std::vector<Located> found;
    if (const std::string missing = locate(jet, output.expression, model, found); !missing.empty()) {
      left_out(output, "output", missing);
      continue;
    }
    for (const Located& l : found)
      if (bound.insert(l.coordinate).second) sources_.push_back({jet.symbol(l.coordinate), l.derivative, l.index});
    names_.push_back(output.name);
    expressions_.push_back(output.expression.subs(parameters, GiNaC::subs_options::no_pattern));
  }
  // The header holds the invariants the model computes (emit's invariants_in_states, which
  // refuses a required one); the others are named here with the reason.
  for (const SceneQuantity& invariant : scene.invariants) {
    bool computed = false;
    for (int k = 0; k < model.n_invariants(); ++k) computed = computed || invariant.name == model.table().invariant_names[k];
    std::vector<Located> found;
    const std::string missing = locate(jet, invariant.expression, model, found);
    if (!computed) left_out(invariant, "invariant", missing.empty() ? "a quantity" : missing);
  }
}

std::vector<double> SceneOutputs::evaluate(const runtime::Sample& sample) const {
  GiNaC::exmap values;
  values[time_] = sample.t;
  for (const Source& s : sources_)
    values[s.symbol] = (s.derivative ? sample.yp : sample.y)[static_cast<std::size_t>(s.index)];
  std::vector<double> out;
  out.reserve(expressions_.size());
  for (const GiNaC::ex& e : expressions_) {
    double v = NAN;
    try {
      const GiNaC::ex value = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
      if (GiNaC::is_a<GiNaC::numeric>(value) && value.info(GiNaC::info_flags::real))
        v = GiNaC::ex_to<GiNaC::numeric>(value).to_double();
    } catch (const std::exception&) {  // a pole: 1/x at x = 0
    }
    out.push_back(std::isfinite(v) ? v : NAN);
  }
  return out;
}

}  // namespace nhc::cli
