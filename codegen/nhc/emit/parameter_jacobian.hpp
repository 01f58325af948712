#pragma once
/// \file parameter_jacobian.hpp
/// \brief The symbolic derivatives forward sensitivities need beyond the iteration matrix
/// (docs/generated-code.md, "Sensitivity additions"): dF/dp of the index-1 residual and dg/dp of
/// the hidden constraints, which fix the consistent initial values (differentiating g(t0, y0, p) = 0
/// gives the initial sensitivities, docs/runtime.md).

#include <ginac/ginac.h>

#include <vector>

#include "nhc/analysis/index1_system.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// Column-major matrices of partial derivatives with respect to the parameters the header reads
/// (PreparedModel::parameters), in that order. Entries not identically zero are listed in `residual_nonzeros` /
/// `hidden_nonzeros` (positions into the column-major arrays, increasing).
struct ParameterJacobian {
  int n_states = 0, n_hidden = 0, n_parameters = 0;
  std::vector<GiNaC::ex> residual;  ///< dF_i/dp_k at i + n_states k
  std::vector<GiNaC::ex> hidden;    ///< dg_r/dp_k at r + n_hidden k
  std::vector<int> residual_nonzeros, hidden_nonzeros;
};

/// dF/dp and dg/dp of `system` for the scene parameters `parameters` (indices into the scene's
/// list); only the parameters occurring in an expression are differentiated. With `inputs`
/// (the scene's [inputs]), dF/dp is the total derivative with each input at its default signal
/// s_j(t, p): ∂F/∂p + Σ_j ∂F/∂u_j ∂s_j/∂p (the sensitivities of a run driven by the default signals).
ParameterJacobian parameter_jacobian(const Index1System& system, const std::vector<int>& parameters,
                                     const std::vector<SceneInput>& inputs = {});

}  // namespace nhc
