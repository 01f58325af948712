#pragma once
/// \file sensitivity.hpp
/// \brief Forward sensitivities s_k = ∂y/∂θ_k of a generated model's solution with SUNDIALS IDAS
/// (Hindmarsh & Serban, IDAS guide, ch. 5; staggered corrector), for θ among the parameters and
/// the given initial values (docs/runtime.md, "Sensitivities").
///
/// s_k solves the sensitivity DAE  F_y s_k + F_y' s_k' + ∂F/∂θ_k = 0  (∂F/∂θ_k = dF/dp_k of the
/// generated Sensitivity additions, 0 for an initial value). Its initial value differentiates the
/// consistent initialization: the given differential states are fixed (s = e_i for θ = their own
/// initial value, plus ∂y_i(t0)/∂θ where the scene writes y_i(t0) through θ), the other differential states solve the
/// hidden constraints g(t0, y0, p) = 0, so
///   G_free s_free = −(G_fixed s_fixed + ∂g/∂θ_k)  (minimum-norm solution, as the states themselves),
/// and IDACalcIC then makes the algebraic components and s' consistent.

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "nhc/base/errors.hpp"
#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/model.hpp"

namespace nhc::runtime {

/// One quantity the solution is differentiated by.
struct SensitivityParameter {
  /// `start`: a parameter of the scene that the model's equations do not read but its given
  /// initial values are written through (x(0) = A): only s(t0) = initial_slope is not zero.
  enum class Kind { parameter, initial_value, start };
  Kind kind = Kind::parameter;
  int index = 0;     ///< parameter index, or state index of the initial value (-1 for start)
  std::string name;  ///< "alpha", "x'(0)", "lambda1(0)"
  /// ∂y_i(t0)/∂θ of the given states whose initial values are written through θ (per state,
  /// empty for none): the start the sensitivities differentiate, besides e_i of an initial value.
  std::vector<double> initial_slope;
  double value = 0;  ///< θ's value for a start parameter (the scale of its sensitivities' tolerances)
};

/// `name` for `model`: a parameter name (`g`), or a state with `(0)` (`x(0)`, `x'(0)`,
/// `lambda1(0)`) for its initial value. Throws std::invalid_argument in words (unknown name, an
/// algebraic state, whose initial value is not free).
SensitivityParameter sensitivity_parameter(const Model& model, const std::string& name);

/// sensitivity_parameter of each name; std::invalid_argument also for a name given twice.
std::vector<SensitivityParameter> sensitivity_parameters(const Model& model, const std::vector<std::string>& names);

/// std::invalid_argument in words for an initial-value θ whose state `initial` does not give: the
/// hidden constraints fix it from the given values, so it cannot be varied on its own.
void require_given(const std::vector<SensitivityParameter>& thetas, const InitialState& initial);

struct SensitivityOptions {
  /// Include the sensitivities in IDAS's local error test (IDASetSensErrCon). Off: the steps are
  /// chosen for y alone and the sensitivities follow (cheaper, less accurate); their corrector
  /// then iterates until its measured contraction says it has converged (sensitivity.cpp).
  bool error_control = true;
};

struct SensitivitySample {
  double t = 0;
  std::vector<double> y, yp;
  std::vector<std::vector<double>> s, sp;  ///< s[k][i] = ∂y_i/∂θ_k, sp[k][i] = ∂y'_i/∂θ_k
  std::vector<double> u;                   ///< the inputs (their default signals) at t
  Sample state() const { return Sample{t, y, yp, u}; }
};

struct SensitivityStatistics {
  Statistics state;                           ///< as for a plain run (IDAS counts the state's work here)
  long sensitivity_residual_evaluations = 0;  ///< calls of the sensitivity residual (all θ at once)
  long sensitivity_error_test_failures = 0;
  long sensitivity_nonlinear_iterations = 0;
};

/// A run of a model with its forward sensitivities. The model needs its Jacobian (dense or
/// sparse) and, when any θ is a parameter, the generated dF/dp (jit::BuildOptions::sensitivities,
/// `nhc generate --sensitivities`). Projection onto the hidden constraints is not used.
class SensitivityIntegrator {
 public:
  SensitivityIntegrator(Model model, std::vector<double> parameters, std::vector<SensitivityParameter> thetas,
                        IntegratorOptions options = {}, SensitivityOptions sensitivity = {});
  ~SensitivityIntegrator();
  SensitivityIntegrator(SensitivityIntegrator&&) noexcept;
  SensitivityIntegrator& operator=(SensitivityIntegrator&&) noexcept;

  /// Consistent initial point and sensitivities. An initial-value θ must be a state that
  /// `state.given` marks (the others follow from the hidden constraints): else SolverError.
  SensitivitySample initialize(const InitialState& state, double t_next);

  /// Through `times` (increasing); the observer sees each output. Throws SolverError with t.
  void integrate(const std::vector<double>& times, const std::function<void(const SensitivitySample&)>& observer);

  SensitivityStatistics statistics() const;
  const std::vector<SensitivityParameter>& thetas() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A whole run, as runtime::simulate: the samples up to a failure are kept.
struct SensitivityRun {
  std::vector<SensitivitySample> samples;
  SensitivityStatistics statistics;
  std::optional<base::SolverError> failure;
};

SensitivityRun simulate_sensitivities(const Model& model, const std::vector<double>& p, const InitialState& initial,
                                      const std::vector<SensitivityParameter>& thetas, const std::vector<double>& times,
                                      const IntegratorOptions& options = {},
                                      const SensitivityOptions& sensitivity = {});

/// Column names `d(<column>)/d(<θ>)` for every state column of csv_header (x, x', x'' …,
/// multipliers), θ by θ.
std::vector<std::string> sensitivity_csv_header(const Model& model, const std::vector<SensitivityParameter>& thetas);

/// The values of sensitivity_csv_header's columns at one sample.
void sensitivity_values(const Model& model, const SensitivitySample& sample, std::vector<double>& values);

/// write_csv's columns followed by the sensitivity columns.
void write_sensitivity_csv(std::ostream& out, const Model& model, const std::vector<double>& p,
                           const std::vector<SensitivityParameter>& thetas,
                           const std::vector<SensitivitySample>& samples);

}  // namespace nhc::runtime
