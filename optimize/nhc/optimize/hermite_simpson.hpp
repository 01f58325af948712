#pragma once
/// \file hermite_simpson.hpp
/// \brief The optimal-control problem of a scene's [optimize] table transcribed by
/// Hermite–Simpson collocation (docs/optimize.md, "Transcription") into a sparse nonlinear
/// program: variables, bounds, objective, constraints and their exact first derivatives.
///
/// Points j = 0 … 2N: the N + 1 mesh nodes (even j) and the N interval midpoints (odd j), at
/// t_j = t0 + (T - t0) j / (2N). Each point holds q (the coordinates) and v = q' (their rates,
/// the controls); a free final time adds T as the last variable.

#include <string>
#include <vector>

#include "nhc/optimize/path_functions.hpp"
#include "nhc/optimize/settings.hpp"

namespace nhc::optimize {

class HermiteSimpson {
 public:
  /// InputError at the entry for a boundary value or bound the transcription cannot take (an
  /// input, a derivative above the first, a boundary value outside its bound).
  HermiteSimpson(const Scene& scene, const Settings& settings, int intervals);

  int intervals() const noexcept { return n_intervals_; }
  int points() const noexcept { return 2 * n_intervals_ + 1; }
  int coordinates() const noexcept { return n_; }
  int variables() const noexcept { return points() * 2 * n_ + (free_time_ ? 1 : 0); }
  int constraints() const noexcept { return n_intervals_ * 2 * n_ + points() * m_; }
  int jacobian_nonzeros() const noexcept;

  int q_index(int point, int i) const noexcept { return point * 2 * n_ + i; }
  int v_index(int point, int i) const noexcept { return point * 2 * n_ + n_ + i; }
  double final_time(const double* z) const noexcept { return free_time_ ? z[variables() - 1] : t_end_low_; }
  double time(int point, const double* z) const noexcept;

  void variable_bounds(double* low, double* high) const;
  double objective(const double* z);
  void objective_gradient(const double* z, double* gradient);
  void constraint_values(const double* z, double* g);
  void jacobian_structure(int* rows, int* columns) const;
  void jacobian_values(const double* z, double* values);

  /// The boundary values joined by straight lines (constant rates); a free final time starts
  /// at the middle of its bounds.
  std::vector<double> straight_line() const;
  /// A path (samples of t, q, q') resampled onto the points by linear interpolation; `columns`
  /// holds each coordinate's column and its rate's (-1 where absent: the rate then follows from
  /// the interpolated q).
  std::vector<double> from_samples(const std::vector<std::vector<double>>& rows, int time_column,
                                   const std::vector<int>& q_columns, const std::vector<int>& v_columns) const;

  /// Constraint row `row` in words with its place: "the constraint z' - (x*y' - y*x')/2 at t = 0.35".
  std::string constraint_name(int row, const double* z) const;

 private:
  void evaluate_points(const double* z);

  int n_, m_, n_intervals_;
  double t0_, t_end_low_, t_end_high_;
  bool free_time_;
  PathFunctions functions_;
  std::vector<std::string> coordinate_names_;
  std::vector<double> low_, high_;  ///< variable bounds
  /// Per point: integrand, constraints (and the final cost at the last point), at the z of cached_.
  std::vector<std::vector<ValueGradient>> at_;
  std::vector<double> cached_;
};

}  // namespace nhc::optimize
