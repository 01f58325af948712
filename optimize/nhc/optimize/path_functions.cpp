#include "nhc/optimize/path_functions.hpp"

namespace nhc::optimize {

namespace {

/// The expression's jet coordinates must be t, q and q': a higher derivative or a multiplier is
/// refused at `where`.
void check_first_order(const JetSpace& jet, const GiNaC::ex& e, const SourceLocation& where, const std::string& what) {
  for (const JetCoordinate& c : jet.jet_coordinates_in(e)) {
    if (c.kind != VariableKind::coordinate)
      throw InputError(where, what + " uses the multiplier " + jet.variable_name(c.kind, c.index) +
                                  ": nhc optimize takes coordinates and their first derivatives");
    if (c.order > 1)
      throw InputError(where, what + " uses " + jet.coordinates()[static_cast<std::size_t>(c.index)] +
                                  std::string(static_cast<std::size_t>(c.order), '\'') +
                                  ": nhc optimize so far takes coordinates and their first derivatives "
                                  "(the derivatives are the controls: docs/optimize.md, \"Scope\")");
  }
}

}  // namespace

PathFunctions::PathFunctions(const Scene& scene, const Settings& settings)
    : n_(scene.coordinate_count()), m_(scene.constraint_count()), constraint_texts_(scene.constraint_texts) {
  const JetSpace& jet = *scene.jet;
  const GiNaC::exmap parameters = scene.parameter_substitution();
  std::vector<GiNaC::ex> functions{settings.objective.subs(parameters)};
  check_first_order(jet, functions[0], settings.objective_where, "the objective");
  for (int a = 0; a < m_; ++a) {
    functions.push_back(scene.constraints[static_cast<std::size_t>(a)].subs(parameters));
    check_first_order(jet, functions.back(), scene.file_location(), "the constraint " + constraint_texts_[static_cast<std::size_t>(a)]);
  }
  functions.push_back(settings.final_cost.subs(parameters));
  check_first_order(jet, functions.back(), settings.final_cost_where, "final_cost");

  std::vector<GiNaC::ex> symbols{jet.time()};
  for (int i = 0; i < n_; ++i) symbols.push_back(jet.q(i, 0));
  for (int i = 0; i < n_; ++i) symbols.push_back(jet.q(i, 1));
  program_ = std::make_unique<NumericProgram>(symbols);
  for (const GiNaC::ex& f : functions)
    for (const GiNaC::ex& s : symbols) {
      if (s.is_equal(symbols.front())) program_->add(f);
      program_->add(f.diff(GiNaC::ex_to<GiNaC::symbol>(s)));
    }
  values_.assign(functions.size(), ValueGradient{0, 0, std::vector<double>(static_cast<std::size_t>(n_)),
                                                 std::vector<double>(static_cast<std::size_t>(n_))});
  inputs_.resize(symbols.size());
}

void PathFunctions::evaluate(double t, const double* q, const double* v) {
  inputs_[0] = t;
  for (int i = 0; i < n_; ++i) {
    inputs_[static_cast<std::size_t>(1 + i)] = q[i];
    inputs_[static_cast<std::size_t>(1 + n_ + i)] = v[i];
  }
  const std::vector<double> out = program_->values_at(inputs_);
  std::size_t k = 0;
  for (ValueGradient& f : values_) {
    f.value = out[k++];
    f.dt = out[k++];
    for (double& d : f.dq) d = out[k++];
    for (double& d : f.dv) d = out[k++];
  }
}

}  // namespace nhc::optimize
