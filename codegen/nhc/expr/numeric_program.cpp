#include "nhc/expr/numeric_program.hpp"

#include <cmath>
#include <map>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> input_names(const std::vector<GiNaC::ex>& inputs) {
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names;
  for (std::size_t k = 0; k < inputs.size(); ++k) names[inputs[k]] = std::to_string(k);
  return names;
}

}  // namespace

NumericProgram::NumericProgram(const std::vector<GiNaC::ex>& inputs) : dag_(input_names(inputs)) {}

int NumericProgram::add(const GiNaC::ex& e, std::string label) {
  outputs_.push_back(dag_.add(e));
  labels_.push_back(std::move(label));
  prepared_ = false;
  return static_cast<int>(outputs_.size()) - 1;
}

void NumericProgram::prepare() const {
  std::vector<EvaluationProgram::Output> outputs;
  for (std::size_t k = 0; k < outputs_.size(); ++k) outputs.push_back({outputs_[k], 0, static_cast<int>(k)});
  program_ = EvaluationProgram(dag_, outputs, [](const Instruction& in) {
    return EvaluationProgram::InputLocation{0, std::stoi(in.name)};
  });
  prepared_ = true;
}

std::vector<double> NumericProgram::evaluate(const std::vector<double>& values, const std::string& what) const {
  std::vector<double> out = values_at(values);
  for (std::size_t k = 0; k < out.size(); ++k)
    if (!std::isfinite(out[k]))
      throw MathError(labels_[k].empty() ? what + " is not finite there (output " + std::to_string(k + 1) + ")"
                                         : labels_[k] + " is not finite there");
  return out;
}

std::vector<double> NumericProgram::values_at(const std::vector<double>& values) const {
  if (!prepared_) prepare();
  std::vector<double> out(outputs_.size(), 0.0);
  const double* arguments[] = {values.data()};
  double* results[] = {out.data()};
  std::vector<double> registers;
  program_.run(arguments, results, registers);
  return out;
}

}  // namespace nhc
