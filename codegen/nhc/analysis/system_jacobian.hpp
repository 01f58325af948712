#pragma once
/// \file system_jacobian.hpp
/// \brief Pryce's system Jacobian J_ij = ∂f_i/∂x_j^(d_j − c_i) where d_j − c_i = σ_ij, else 0
/// (models.md, "Structural analysis", step 4; Pryce, BIT 41 (2001), eq. (3.4)). It is also
/// the Jacobian of the differentiated equations D^{c_i} f_i with respect to the leading
/// derivatives x_j^(d_j) (Griewank's lemma), so the Σ-method succeeds at a consistent point
/// exactly when J is nonsingular there, and then the index-1 form is index 1 there.

#include <ginac/ginac.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "nhc/analysis/structural_analysis.hpp"

namespace nhc {

/// Symbolic J (rows equations, columns unknowns). Requires a nonsingular structure.
std::vector<std::vector<GiNaC::ex>> system_jacobian(const StructuralAnalysis& analysis);

/// J is taken as singular when its condition number exceeds this.
inline constexpr double kSingularCondition = 1e12;

/// Words for a (numerically) singular J: which equations are dependent in their leading
/// derivatives (left null vector) and which leading derivatives are not determined
/// (right null vector), from the SVD.
std::string describe_singular_jacobian(const StructuralAnalysis& analysis, const Eigen::MatrixXd& j,
                                       double t0);

}  // namespace nhc
