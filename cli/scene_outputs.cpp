#include "scene_outputs.hpp"

#include <cmath>
#include <set>

#include "nhc/errors.hpp"

namespace nhc::cli {

namespace {

std::string primed(const std::string& variable, int order) {
  return variable + std::string(static_cast<std::size_t>(order), '\'');
}

}  // namespace

SceneOutputs::SceneOutputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : time_(scene.jet->time()) {
  const JetSpace& jet = *scene.jet;
  GiNaC::exmap parameters;
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k) {
    const int i = model.parameter_index(jet.parameters()[static_cast<std::size_t>(k)]);
    if (i >= 0) parameters[jet.parameter(k)] = p.at(static_cast<std::size_t>(i));
  }
  std::set<JetCoordinate> bound;
  for (const SceneOutput& output : scene.outputs) {
    for (const JetCoordinate& c : jet.jet_coordinates_in(output.expression)) {
      if (bound.count(c)) continue;
      // The state holding this derivative, else the derivative y' of the state one order below.
      const int variable = c.kind == VariableKind::coordinate ? c.index : model.n_coordinates() + c.index;
      const bool known = c.kind == VariableKind::coordinate || c.index < model.n_multipliers();
      const int state = known ? model.state_index(variable, c.order) : -1;
      const int below = known && c.order > 0 ? model.state_index(variable, c.order - 1) : -1;
      if (state >= 0) {
        sources_.push_back({jet.symbol(c), false, state});
      } else if (below >= 0 && model.is_differential(below)) {
        sources_.push_back({jet.symbol(c), true, below});
      } else {
        const std::string name = primed(jet.variable_name(c.kind, c.index), c.order);
        throw InputError(output.where, "output '" + output.name + "' uses " + name + ", which the " +
                                           model.model_name() + " model does not compute" +
                                           (known ? "" : " (it has no multiplier " + jet.variable_name(c.kind, c.index) + ")"));
      }
      bound.insert(c);
    }
    names_.push_back(output.name);
    expressions_.push_back(output.expression.subs(parameters, GiNaC::subs_options::no_pattern));
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
