#include "nhc/optimize/path_functions.hpp"

#include "nhc/jet/intermediate.hpp"

namespace nhc::optimize {

PathFunctions::PathFunctions(const PointProblem& problem) : slot_count_(problem.slots()) {
  std::vector<GiNaC::ex> functions{problem.integrand, problem.final_cost};
  for (const PointRow& r : problem.path) functions.push_back(r.expression);
  for (const PointRow& r : problem.initial_rows) functions.push_back(r.expression);

  program_ = std::make_unique<NumericProgram>(problem.symbols);
  const GiNaC::symbol& t = GiNaC::ex_to<GiNaC::symbol>(problem.symbols.front());
  for (const GiNaC::ex& f : functions) {
    std::vector<int> slots;
    program_->add(f);
    program_->add(f.diff(t));
    for (int s = 0; s < slot_count_; ++s) {
      const GiNaC::ex& symbol = problem.symbols[static_cast<std::size_t>(1 + s)];
      if (!depends_on(f, symbol)) continue;
      slots.push_back(s);
      program_->add(f.diff(GiNaC::ex_to<GiNaC::symbol>(symbol)));
    }
    values_.push_back({0, 0, std::vector<double>(slots.size())});
    slots_.push_back(std::move(slots));
  }
  inputs_.assign(problem.symbols.size(), 0.0);
  std::copy(problem.parameter_values.begin(), problem.parameter_values.end(), inputs_.begin() + 1 + slot_count_);
}

void PathFunctions::evaluate(double t, const double* point) {
  inputs_[0] = t;
  std::copy(point, point + slot_count_, inputs_.begin() + 1);
  const std::vector<double> out = program_->values_at(inputs_);
  std::size_t k = 0;
  for (ValueGradient& f : values_) {
    f.value = out[k++];
    f.dt = out[k++];
    for (double& d : f.d) d = out[k++];
  }
}

}  // namespace nhc::optimize
