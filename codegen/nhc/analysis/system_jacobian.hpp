#pragma once
/// \file system_jacobian.hpp
/// \brief Pryce's system Jacobian J_ij = ∂f_i/∂x_j^(d_j − c_i) where d_j − c_i = σ_ij, else 0
/// (models.md, "Structural analysis", step 4; Pryce, BIT 41 (2001), eq. (3.4)). It is also
/// the Jacobian of the differentiated equations D^{c_i} f_i with respect to the leading
/// derivatives x_j^(d_j) (Griewank's lemma), so the Σ-method succeeds at a consistent point
/// exactly when J is nonsingular there, and then the index-1 form is index 1 there.

#include <ginac/ginac.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <string>
#include <vector>

#include "nhc/analysis/structural_analysis.hpp"

namespace nhc {

/// One structurally nonzero entry J_ij.
struct JacobianEntry {
  int row = 0;
  int col = 0;
  GiNaC::ex value;
};

/// The entries of J that are not identically zero, row by row: one derivative per finite σ_ij
/// on d_j − c_i, so the work follows the number of entries of σ, not its N² size. Requires a
/// nonsingular structure.
std::vector<JacobianEntry> system_jacobian_entries(const StructuralAnalysis& analysis);

/// Symbolic J as a dense n×n array (rows equations, columns unknowns), for small systems.
std::vector<std::vector<GiNaC::ex>> system_jacobian(const StructuralAnalysis& analysis);

/// J at `point` (symbol → number), sparse; `what` names J in messages.
Eigen::SparseMatrix<double> evaluate_system_jacobian(const std::vector<JacobianEntry>& entries, int n,
                                                     const GiNaC::exmap& point, const std::string& what);

/// Up to this size describe_singular_jacobian names the dependent equations from a dense SVD.
inline constexpr int kDescribedSingularLimit = 2000;

/// J is taken as singular when its condition number exceeds this.
inline constexpr double kSingularCondition = 1e12;

/// Words for a (numerically) singular J: which equations are dependent in their leading
/// derivatives (left null vector) and which leading derivatives are not determined
/// (right null vector), from the SVD; above kDescribedSingularLimit unknowns only the size and
/// the condition number (an SVD would take O(n³)).
std::string describe_singular_jacobian(const StructuralAnalysis& analysis, const Eigen::SparseMatrix<double>& j,
                                       double t0);

}  // namespace nhc
