#pragma once
/// \file spectrum.hpp
/// \brief Eigenvalues of A and the stability verdict (docs/linearize.md, "Verdict").

#include <Eigen/Dense>

#include <complex>
#include <vector>

#include "nhc/linearize/linearization.hpp"

namespace nhc {

/// Eigenvalues sorted by real part (largest first), then imaginary part (largest first).
std::vector<std::complex<double>> sorted_eigenvalues(const Eigen::MatrixXd& A);

/// Eigenvalues with |λ| ≤ zero_tolerance·max(1, ‖A‖_∞).
int count_zero_eigenvalues(const Eigen::MatrixXd& A, const std::vector<std::complex<double>>& eigenvalues,
                           double zero_tolerance);

/// With scale = max(1, ‖A‖_∞): zero when |λ| ≤ zero_tolerance·scale; `families` of the zero
/// eigenvalues are explained (families of steady motions). unstable when some other
/// Re λ > tolerance·scale; asymptotically_stable when every other λ has Re λ < −tolerance·scale
/// and every zero eigenvalue is explained; marginally_stable otherwise.
StabilityVerdict classify_spectrum(const Eigen::MatrixXd& A, const std::vector<std::complex<double>>& eigenvalues,
                                   int families, double tolerance, double zero_tolerance);

}  // namespace nhc
