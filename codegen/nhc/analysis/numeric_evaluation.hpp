#pragma once
/// \file numeric_evaluation.hpp
/// \brief Evaluating symbolic expressions at a numeric point with GiNaC (substitute, evalf),
/// with failures turned into MathError in words.

#include <ginac/ginac.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <string>
#include <vector>

namespace nhc {

/// e at `point` (symbol → number); `what` names e in messages. Throws MathError when the
/// result is not a finite real number (division by zero, square root of a negative number,
/// a symbol without a value).
double evaluate_real(const GiNaC::ex& e, const GiNaC::exmap& point, const std::string& what);

/// 2-norm condition number σ_max/σ_min; +∞ when σ_min = 0; 1 for an empty matrix.
double condition_number(const Eigen::MatrixXd& m);

/// Up to this size a sparse matrix's condition number is the exact 2-norm one (dense SVD,
/// O(n³)); above it, the 1-norm estimate below (docs/analysis.md).
inline constexpr int kExactConditionLimit = 400;

/// A condition number and how it was obtained.
struct ConditionNumber {
  double value = 1.0;
  bool estimated = false;  ///< false: exact 2-norm κ₂; true: 1-norm estimate of κ₁
};

/// κ₂ exactly (dense SVD) for n ≤ kExactConditionLimit, else condition_estimate_1norm.
ConditionNumber condition_number(const Eigen::SparseMatrix<double>& m);

/// κ₁(A) = ‖A‖₁·‖A⁻¹‖₁ with ‖A⁻¹‖₁ estimated from a sparse LU factorization by Hager's method
/// in Higham's form (Hager 1984; Higham, ACM TOMS 14 (1988) 381–396, Alg. 4.1, LAPACK xLACON):
/// a few solves with A and Aᵀ, never A⁻¹ itself. The estimate is a lower bound of κ₁, almost
/// always within a factor 3 of it; κ₁/n ≤ κ₂ ≤ n·κ₁. +∞ when the LU finds an exactly zero pivot.
double condition_estimate_1norm(const Eigen::SparseMatrix<double>& m);

}  // namespace nhc
