#include "nhc/runtime/inputs.hpp"

#include "nhc/base/errors.hpp"

namespace nhc::runtime {

InputValues::InputValues(const Model& model, std::vector<double> parameters)
    : table_(&model.table()),
      n_parameters_(model.n_parameters()),
      n_inputs_(model.n_inputs()),
      parameters_(std::move(parameters)) {
  if (static_cast<int>(parameters_.size()) != n_parameters_)
    throw base::ModelError("the model has " + std::to_string(n_parameters_) + " parameters, " +
                           std::to_string(parameters_.size()) + " given");
  p_ = parameters_;
  p_.resize(static_cast<std::size_t>(n_parameters_ + n_inputs_), 0.0);
}

const double* InputValues::at(double t, const double* y) const {
  double* u = p_.data() + n_parameters_;
  switch (source_) {
    case Source::defaults:
      if (n_inputs_ > 0) table_->default_inputs(t, p_.data(), u);
      break;
    case Source::function:
      function_(t, y, u);
      break;
    case Source::held:
      break;
  }
  return p_.data();
}

void InputValues::set_function(InputFunction f) {
  if (!f) throw base::ModelError("an input function must not be empty");
  function_ = std::move(f);
  source_ = Source::function;
}

void InputValues::hold(std::vector<double> values) {
  if (static_cast<int>(values.size()) != n_inputs_)
    throw base::ModelError("the model has " + std::to_string(n_inputs_) + " inputs, " + std::to_string(values.size()) +
                           " values given");
  std::copy(values.begin(), values.end(), p_.begin() + n_parameters_);
  source_ = Source::held;
}

}  // namespace nhc::runtime
