#include "nhc/linearize/spectrum.hpp"

#include <algorithm>
#include <cmath>

namespace nhc {

std::string to_string(StabilityVerdict verdict) {
  switch (verdict) {
    case StabilityVerdict::unstable:
      return "unstable";
    case StabilityVerdict::marginally_stable:
      return "marginally_stable";
    case StabilityVerdict::asymptotically_stable:
      return "asymptotically_stable";
  }
  return "?";
}

std::vector<std::complex<double>> sorted_eigenvalues(const Eigen::MatrixXd& A) {
  std::vector<std::complex<double>> out;
  if (A.size() == 0) return out;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(A, false);
  const Eigen::VectorXcd values = solver.eigenvalues();
  out.assign(values.data(), values.data() + values.size());
  // Real parts equal to rounding are sorted by imaginary part, so that a conjugate pair on the
  // axis and zeros keep one order along a sweep.
  const double close = 1e-9 * std::max(1.0, A.cwiseAbs().rowwise().sum().maxCoeff());
  std::stable_sort(out.begin(), out.end(), [close](const std::complex<double>& a, const std::complex<double>& b) {
    const double ka = std::round(a.real() / close), kb = std::round(b.real() / close);  // a strict weak order
    if (ka != kb) return ka > kb;
    return a.imag() > b.imag();
  });
  return out;
}

namespace {
double scale_of(const Eigen::MatrixXd& A) {
  return A.size() ? std::max(1.0, A.cwiseAbs().rowwise().sum().maxCoeff()) : 1.0;
}
}  // namespace

int count_zero_eigenvalues(const Eigen::MatrixXd& A, const std::vector<std::complex<double>>& eigenvalues,
                           double zero_tolerance) {
  int zeros = 0;
  for (const std::complex<double>& l : eigenvalues) zeros += std::abs(l) <= zero_tolerance * scale_of(A) ? 1 : 0;
  return zeros;
}

StabilityVerdict classify_spectrum(const Eigen::MatrixXd& A, const std::vector<std::complex<double>>& eigenvalues,
                                   int families, double tolerance, double zero_tolerance) {
  const double scale = scale_of(A);
  int zeros = 0;
  bool positive = false, on_axis = false;
  for (const std::complex<double>& l : eigenvalues) {
    if (std::abs(l) <= zero_tolerance * scale) {
      ++zeros;
      continue;
    }
    if (l.real() > tolerance * scale) positive = true;
    else if (l.real() >= -tolerance * scale) on_axis = true;
  }
  if (zeros > families) on_axis = true;
  return positive  ? StabilityVerdict::unstable
         : on_axis ? StabilityVerdict::marginally_stable
                   : StabilityVerdict::asymptotically_stable;
}

}  // namespace nhc
