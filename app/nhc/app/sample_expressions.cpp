#include "nhc/app/sample_expressions.hpp"

#include "nhc/base/primed_name.hpp"

#include <cmath>
#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/long_work.hpp"

namespace nhc::app {

namespace {

std::string primed(const std::string& variable, int order) { return base::primed_name(variable, order); }

}  // namespace

SampleExpressions::SampleExpressions(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : scene_(&scene), model_(&model) {
  const JetSpace& jet = *scene.jet;
  // The model's values, and the scene's for a parameter only these expressions use (it is not
  // in the header; --set has given it to the scene).
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k) {
    const int i = model.parameter_index(jet.parameters()[static_cast<std::size_t>(k)]);
    parameters_[jet.parameter(k)] =
        i >= 0 ? p.at(static_cast<std::size_t>(i)) : scene.parameter_values.at(static_cast<std::size_t>(k));
  }
}

SampleExpressions::SampleExpressions(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                                     std::vector<GiNaC::ex> free)
    : SampleExpressions(scene, model, p) {
  free_ = std::move(free);
}

std::string SampleExpressions::locate(const GiNaC::ex& e, std::vector<Source>& found) const {
  const JetSpace& jet = *scene_->jet;
  const runtime::Model& model = *model_;
  // Every jet symbol of e in the model's samples: the state holding it, else the derivative y'
  // of the state one order below.
  for (const JetCoordinate& c : jet.jet_coordinates_in(e)) {
    const int variable = c.kind == VariableKind::coordinate ? c.index : model.n_coordinates() + c.index;
    const bool known = c.kind == VariableKind::coordinate || c.index < model.n_multipliers();
    const int state = known ? model.state_index(variable, c.order) : -1;
    const int below = known && c.order > 0 ? model.state_index(variable, c.order - 1) : -1;
    if (state >= 0) found.push_back({jet.symbol(c), Slot::state, state});
    else if (below >= 0 && model.is_differential(below)) found.push_back({jet.symbol(c), Slot::derivative, below});
    else
      return primed(jet.variable_name(c.kind, c.index), c.order) +
             (known ? "" : " (it has no multiplier " + jet.variable_name(c.kind, c.index) + ")");
  }
  // Inputs: their values at the sample, as the run evaluated them (Sample::u, the model's order).
  for (int k = 0; k < static_cast<int>(jet.inputs().size()); ++k) {
    if (!e.has(jet.input(k))) continue;
    const int i = model.input_index(jet.inputs()[static_cast<std::size_t>(k)]);
    if (i < 0) return jet.inputs()[static_cast<std::size_t>(k)] + " (an input the model does not read)";
    found.push_back({jet.input(k), Slot::input, i});
  }
  return "";
}

double SampleExpressions::value_of(const Source& s, const runtime::Sample& sample) {
  const std::vector<double>& from = s.slot == Slot::state        ? sample.y
                                    : s.slot == Slot::derivative ? sample.yp
                                                                 : sample.u;
  const auto k = static_cast<std::size_t>(s.index);
  return k < from.size() ? from[k] : NAN;  // a sample without inputs (read back from a file): NaN
}

std::string SampleExpressions::missing(const GiNaC::ex& expression) const {
  std::vector<Source> found;
  return locate(expand_intermediates(expression), found);
}

std::string SampleExpressions::add(const GiNaC::ex& expression) {
  const GiNaC::ex e = expand_intermediates(expression);
  std::vector<Source> found;
  if (std::string missing = locate(e, found); !missing.empty()) return missing;
  for (const Source& s : found)
    if (bound_.insert(s.symbol).second) sources_.push_back(s);
  expressions_.push_back(e.subs(parameters_, GiNaC::subs_options::no_pattern));
  program_.reset();
  substitute_ = false;
  return "";
}

void SampleExpressions::prepare() const {
  if (program_ || substitute_) return;
  std::vector<GiNaC::ex> inputs{scene_->jet->time()};
  for (const Source& s : sources_) inputs.push_back(s.symbol);
  inputs.insert(inputs.end(), free_.begin(), free_.end());
  try {
    program_ = std::make_unique<NumericProgram>(inputs);
    for (const GiNaC::ex& e : expressions_) program_->add(e);
    program_->prepare();
  } catch (const MathError&) {  // a function without a double counterpart: GiNaC evaluates
    program_.reset();
    substitute_ = true;
  }
}

std::vector<double> SampleExpressions::evaluate(const runtime::Sample& sample) const { return evaluate(sample, {}); }

std::vector<double> SampleExpressions::evaluate(const runtime::Sample& sample, const std::vector<double>& free) const {
  if (free.size() != free_.size())
    throw std::invalid_argument("SampleExpressions::evaluate: wrong number of free values");
  if (!program_ && !substitute_) {
    const SymbolicSection symbolic;
    prepare();
  }
  std::vector<double> out;
  if (program_) {
    std::vector<double> values{sample.t};
    for (const Source& s : sources_) values.push_back(value_of(s, sample));
    values.insert(values.end(), free.begin(), free.end());
    try {
      out = program_->values_at(values);
    } catch (const MathError&) {  // as above, found while evaluating
      const SymbolicSection symbolic;
      program_.reset();
      substitute_ = true;
    }
  }
  if (!program_) {
    const SymbolicSection symbolic;  // a run may call this without the lock (scene_events.hpp)
    GiNaC::exmap values;
    values[scene_->jet->time()] = sample.t;
    for (const Source& s : sources_) values[s.symbol] = value_of(s, sample);
    for (std::size_t k = 0; k < free_.size(); ++k) values[free_[k]] = free[k];
    for (const GiNaC::ex& e : expressions_) {
      double v = NAN;
      try {
        const GiNaC::ex value = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
        if (GiNaC::is_a<GiNaC::numeric>(value) && value.info(GiNaC::info_flags::real))
          v = GiNaC::ex_to<GiNaC::numeric>(value).to_double();
      } catch (const std::exception&) {  // a pole: 1/x at x = 0
      }
      out.push_back(v);
    }
  }
  for (double& v : out)
    if (!std::isfinite(v)) v = NAN;
  return out;
}

}  // namespace nhc::app
