#pragma once
/// \file inputs.hpp
/// \brief The inputs u of a model during a run (scene [inputs], docs/runtime.md, "Inputs").
///
/// The generated functions read input k at p[n_parameters + k] (docs/generated-code.md, "Input
/// additions"). An InputValues owns that array and fills its inputs before every call, in one
/// of three ways: the model's default signals u(t); an application's function u(t, y), called at
/// every evaluation (a continuous feedback law); or values held constant from a time on, which
/// the application changes between steps (sampled-data control).

#include <functional>
#include <string>
#include <vector>

#include "nhc/runtime/model.hpp"

namespace nhc::runtime {

/// u(t, y): writes the model's n_inputs inputs into u, in Model::input_name order.
using InputFunction = std::function<void(double t, const double* y, double* u)>;

class InputValues {
 public:
  /// The model's default signals; `parameters` of size n_parameters.
  InputValues(const Model& model, std::vector<double> parameters);

  /// p with the inputs at (t, y) written after the parameters: the array each generated
  /// function takes. y may be null for functions of t alone.
  const double* at(double t, const double* y) const;

  /// From now on u(t, y) = f(t, y) at every evaluation.
  void set_function(InputFunction f);
  /// From now on u = values (n_inputs of them), constant until changed.
  void hold(std::vector<double> values);

  int n_inputs() const noexcept { return n_inputs_; }
  const std::vector<double>& parameters() const noexcept { return parameters_; }

 private:
  enum class Source { defaults, function, held };
  const nhc_model_table* table_;
  int n_parameters_ = 0, n_inputs_ = 0;
  std::vector<double> parameters_;
  mutable std::vector<double> p_;  ///< parameters, then the inputs of the last at()
  Source source_ = Source::defaults;
  InputFunction function_;
};

}  // namespace nhc::runtime
