#include "nhc/emit/parameter_jacobian.hpp"

#include <cstddef>
#include <set>

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/partial_derivative.hpp"

namespace nhc {

namespace {

/// Column-major ∂e_i/∂p_k of `expressions` with the positions of the entries that are not zero.
void differentiate(const std::vector<GiNaC::ex>& expressions, const JetSpace& jet, const std::vector<int>& parameters,
                   std::vector<GiNaC::ex>& entries, std::vector<int>& nonzeros) {
  const std::size_t rows = expressions.size();
  const std::size_t columns = parameters.size();
  entries.assign(rows * columns, GiNaC::ex(0));
  std::vector<std::set<GiNaC::ex, GiNaC::ex_is_less>> occurring;  // through named intermediates
  for (const GiNaC::ex& e : expressions) occurring.push_back(symbols_through(e));
  for (std::size_t k = 0; k < columns; ++k) {
    const GiNaC::realsymbol& p = jet.parameter(parameters[k]);
    for (std::size_t i = 0; i < rows; ++i) {
      if (!occurring[i].count(p)) continue;
      const GiNaC::ex d = partial_derivative(expressions[i], p);
      if (d.is_zero()) continue;
      entries[i + rows * k] = d;
      nonzeros.push_back(static_cast<int>(i + rows * k));
    }
  }
}

}  // namespace

ParameterJacobian parameter_jacobian(const Index1System& system, const std::vector<int>& parameters,
                                     const std::vector<SceneInput>& inputs) {
  ParameterJacobian out;
  out.n_states = system.size();
  out.n_hidden = static_cast<int>(system.hidden_constraints.size());
  out.n_parameters = static_cast<int>(parameters.size());
  differentiate(system.residuals, *system.jet, parameters, out.residual, out.residual_nonzeros);
  // The inputs at their default signals s_j(t, p): dF/dp_k gains sum_j dF/du_j ds_j/dp_k.
  const JetSpace& jet = *system.jet;
  const auto rows = static_cast<std::size_t>(out.n_states);
  std::set<int> nonzero(out.residual_nonzeros.begin(), out.residual_nonzeros.end());
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    const GiNaC::realsymbol& u = jet.input(static_cast<int>(j));
    const auto signal_symbols = symbols_through(inputs[j].default_signal);
    for (std::size_t k = 0; k < parameters.size(); ++k) {
      const GiNaC::realsymbol& p = jet.parameter(parameters[k]);
      if (!signal_symbols.count(p)) continue;
      const GiNaC::ex ds = partial_derivative(inputs[j].default_signal, p);
      if (ds.is_zero()) continue;
      for (std::size_t i = 0; i < rows; ++i) {
        if (!symbols_through(system.residuals[i]).count(u)) continue;
        const GiNaC::ex dF = partial_derivative(system.residuals[i], u);
        if (dF.is_zero()) continue;
        out.residual[i + rows * k] += dF * ds;
        nonzero.insert(static_cast<int>(i + rows * k));
      }
    }
  }
  out.residual_nonzeros.assign(nonzero.begin(), nonzero.end());
  differentiate(system.hidden_constraints, *system.jet, parameters, out.hidden, out.hidden_nonzeros);
  return out;
}

}  // namespace nhc
