#include "nhc/optimize/path_functions.hpp"

#include "nhc/expr/intermediate.hpp"

namespace nhc::optimize {

PathFunctions::PathFunctions(const PointProblem& problem) : slot_count_(problem.slots()) {
  std::vector<GiNaC::ex> functions{problem.integrand, problem.final_cost};
  for (const PointRow& r : problem.path) functions.push_back(r.expression);
  for (const PointRow& r : problem.initial_rows) functions.push_back(r.expression);

  program_ = std::make_unique<NumericProgram>(problem.symbols);
  second_ = std::make_unique<NumericProgram>(problem.symbols);
  values_only_ = std::make_unique<NumericProgram>(problem.symbols);
  // Variable -1 is t, k >= 0 the slot k.
  auto symbol = [&](int k) -> const GiNaC::symbol& {
    return GiNaC::ex_to<GiNaC::symbol>(problem.symbols[static_cast<std::size_t>(1 + k)]);
  };
  for (const GiNaC::ex& f : functions) {
    std::vector<int> slots;
    std::vector<VariablePair> pairs;
    program_->add(f);
    values_only_->add(f);
    const GiNaC::ex f_t = f.diff(symbol(-1));
    program_->add(f_t);
    std::vector<std::pair<int, GiNaC::ex>> first{{-1, f_t}};
    for (int s = 0; s < slot_count_; ++s) {
      if (!depends_on(f, problem.symbols[static_cast<std::size_t>(1 + s)])) continue;
      slots.push_back(s);
      first.emplace_back(s, f.diff(symbol(s)));
      program_->add(first.back().second);
    }
    // Second derivatives of each first derivative by the variables it still depends on.
    for (std::size_t a = 0; a < first.size(); ++a)
      for (std::size_t b = 0; b <= a; ++b) {
        const int va = first[a].first, vb = first[b].first;
        if (!depends_on(first[a].second, problem.symbols[static_cast<std::size_t>(1 + vb)])) continue;
        pairs.emplace_back(va, vb);
        second_->add(first[a].second.diff(symbol(vb)));
      }
    values_.push_back({0, 0, std::vector<double>(slots.size()), std::vector<double>(pairs.size())});
    slots_.push_back(std::move(slots));
    pairs_.push_back(std::move(pairs));
  }
  inputs_.assign(problem.symbols.size(), 0.0);
  std::copy(problem.parameter_values.begin(), problem.parameter_values.end(), inputs_.begin() + 1 + slot_count_);
}

void PathFunctions::set_inputs(double t, const double* point) {
  inputs_[0] = t;
  std::copy(point, point + slot_count_, inputs_.begin() + 1);
}

void PathFunctions::evaluate_values(double t, const double* point) {
  set_inputs(t, point);
  const std::vector<double> out = values_only_->values_at(inputs_);
  for (std::size_t f = 0; f < values_.size(); ++f) values_[f].value = out[f];
}

void PathFunctions::evaluate_second(double t, const double* point) {
  set_inputs(t, point);
  const std::vector<double> out = second_->values_at(inputs_);
  std::size_t k = 0;
  for (ValueGradient& f : values_)
    for (double& d : f.dd) d = out[k++];
}

void PathFunctions::evaluate(double t, const double* point) {
  set_inputs(t, point);
  const std::vector<double> out = program_->values_at(inputs_);
  std::size_t k = 0;
  for (ValueGradient& f : values_) {
    f.value = out[k++];
    f.dt = out[k++];
    for (double& d : f.d) d = out[k++];
  }
}

}  // namespace nhc::optimize
