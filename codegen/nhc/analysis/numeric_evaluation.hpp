#pragma once
/// \file numeric_evaluation.hpp
/// \brief Evaluating symbolic expressions at a numeric point with GiNaC (substitute, evalf),
/// with failures turned into MathError in words.

#include <ginac/ginac.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace nhc {

/// e at `point` (symbol → number); `what` names e in messages. Throws MathError when the
/// result is not a finite real number (division by zero, square root of a negative number,
/// a symbol without a value).
double evaluate_real(const GiNaC::ex& e, const GiNaC::exmap& point, const std::string& what);

/// Row-major matrix of expressions evaluated at `point`.
Eigen::MatrixXd evaluate_matrix(const std::vector<std::vector<GiNaC::ex>>& m,
                                const GiNaC::exmap& point, const std::string& what);
Eigen::VectorXd evaluate_vector(const std::vector<GiNaC::ex>& v, const GiNaC::exmap& point,
                                const std::string& what);

/// 2-norm condition number σ_max/σ_min; +∞ when σ_min = 0; 1 for an empty matrix.
double condition_number(const Eigen::MatrixXd& m);

}  // namespace nhc
