#pragma once
/// \file hermite_simpson.hpp
/// \brief The optimal-control problem of a scene's [optimize] table transcribed by
/// Hermite–Simpson collocation (docs/optimize.md, "Transcription") into a sparse nonlinear
/// program: variables, bounds, objective, constraints and their exact first derivatives.
///
/// Points j = 0 … 2N: the N + 1 mesh nodes (even j) and the N interval midpoints (odd j), at
/// t_j = t0 + (T - t0) s_j, s_j the point's fraction of the horizon (a mesh of N intervals given
/// by its node fractions 0 = s_0 < s_2 < … < s_2N = 1; equal intervals by default). Each point holds the PointProblem's
/// slots: the states y, their rates y' and the inputs u (without [inputs]: y = q, y' = q'); a free final time adds T as
/// the last variable.

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "nhc/optimize/path_functions.hpp"
#include "nhc/optimize/point_problem.hpp"
#include "nhc/optimize/settings.hpp"

namespace nhc::optimize {

class HermiteSimpson {
 public:
  /// InputError at the entry for a boundary value or bound the transcription cannot take (a
  /// derivative the states do not hold, a boundary value outside its bound, initial values that
  /// violate a hidden constraint).
  HermiteSimpson(const Scene& scene, const Settings& settings, int intervals);
  HermiteSimpson(const Scene& scene, const Settings& settings, PointProblem problem, int intervals);
  /// On the mesh of node fractions `mesh` (increasing from 0 to 1; its size is intervals + 1).
  HermiteSimpson(const Scene& scene, const Settings& settings, PointProblem problem, std::vector<double> mesh);

  /// The same problem on another mesh, sharing this one's lowered functions (nothing is derived
  /// or lowered again): the rounds of mesh refinement (refine.hpp).
  HermiteSimpson remeshed(std::vector<double> mesh) const;

  /// The receding horizon (model predictive control, docs/mpc.md; a fixed final time): the same
  /// problem, structure and lowered functions over [t0, t0 + its length] from the first point's
  /// values `start` of the point problem's `initial` slots (in their order).
  void restart(double t0, const std::vector<double>& start);

  /// The node fractions of the mesh (size intervals() + 1).
  std::vector<double> mesh() const;
  /// Point j's fraction of the horizon.
  double fraction(int point) const noexcept { return s_[static_cast<std::size_t>(point)]; }
  /// The length of interval k at z.
  double interval_length(int k, const double* z) const noexcept {
    return (final_time(z) - t0_) * (s_[static_cast<std::size_t>(2 * k + 2)] - s_[static_cast<std::size_t>(2 * k)]);
  }
  double initial_time() const noexcept { return t0_; }

  const PointProblem& point_problem() const noexcept { return problem_; }
  /// The point problem's functions, to evaluate between the points (path_error.hpp).
  PathFunctions& functions() noexcept { return *functions_; }
  /// The bounds of variable `index` of the problem.
  double variable_low(int index) const noexcept { return low_[static_cast<std::size_t>(index)]; }
  double variable_high(int index) const noexcept { return high_[static_cast<std::size_t>(index)]; }
  int intervals() const noexcept { return n_intervals_; }
  int points() const noexcept { return 2 * n_intervals_ + 1; }
  int states() const noexcept { return n_; }
  int inputs() const noexcept { return problem_.inputs; }
  /// Without [inputs], the coordinates (= states).
  int coordinates() const noexcept { return n_; }
  int variables() const noexcept { return points() * stride_ + (free_time_ ? 1 : 0); }
  int constraints() const noexcept { return collocation_rows() + points() * path_rows() + initial_rows(); }
  int jacobian_nonzeros() const noexcept;

  /// y_i, y'_i and u_k of point j (without [inputs]: q_i and q'_i).
  int q_index(int point, int i) const noexcept { return point * stride_ + i; }
  int v_index(int point, int i) const noexcept { return point * stride_ + n_ + i; }
  int u_index(int point, int k) const noexcept { return point * stride_ + 2 * n_ + k; }
  double final_time(const double* z) const noexcept { return free_time_ ? z[variables() - 1] : t_end_low_; }
  double time(int point, const double* z) const noexcept;

  void variable_bounds(double* low, double* high) const;
  void constraint_bounds(double* low, double* high) const;
  double objective(const double* z);
  void objective_gradient(const double* z, double* gradient);
  void constraint_values(const double* z, double* g);
  void jacobian_structure(int* rows, int* columns) const;
  void jacobian_values(const double* z, double* values);

  /// The Hessian of the Lagrangian sigma f + sum lambda_r g_r, exact (second derivatives of the
  /// PathProblem's functions), as its lower triangle: structure fixed, values at z.
  int hessian_nonzeros() const noexcept { return static_cast<int>(hessian_entries_.size()); }
  void hessian_structure(int* rows, int* columns) const;
  void hessian_values(const double* z, double sigma, const double* lambda, double* values);

  /// The boundary values joined by straight lines (constant rates); a free final time starts
  /// at the middle of its bounds; inputs at 0 (clamped into their bounds).
  std::vector<double> straight_line() const;
  /// A path (samples of t and of the columns) resampled onto the points by linear interpolation;
  /// per state its column and its rate's, per input its column (-1 where absent: a state's rate
  /// then follows from the interpolated state, anything else keeps straight_line()'s value).
  std::vector<double> from_samples(const std::vector<std::vector<double>>& rows, int time_column,
                                   const std::vector<int>& q_columns, const std::vector<int>& v_columns,
                                   const std::vector<int>& u_columns = {}) const;

  /// Constraint row `row` in words with its place: "the constraint z' - (x*y' - y*x')/2 = 0 at t = 0.35".
  std::string constraint_name(int row, const double* z) const;

 private:
  int collocation_rows() const noexcept { return n_intervals_ * 2 * static_cast<int>(collocated_.size()); }
  int path_rows() const noexcept { return static_cast<int>(problem_.path.size()); }
  int initial_rows() const noexcept { return static_cast<int>(kept_initial_rows_.size()); }
  /// The functions at every point of z, with their first derivatives when `derivatives`.
  void evaluate_points(const double* z, bool derivatives);
  struct Shared {};
  HermiteSimpson(const HermiteSimpson& other, std::vector<double> mesh, Shared);
  void set_up(const std::vector<double>& mesh);
  void drop_fixed_initial_rows();
  void build_hessian_structure();
  int hessian_entry(int row, int column) const;

  PointProblem problem_;
  int n_, stride_, n_intervals_;
  double t0_, t_end_low_, t_end_high_;
  bool free_time_;
  std::shared_ptr<PathFunctions> functions_;
  SourceLocation initial_where_;        ///< where a violated hidden constraint is reported
  std::vector<int> collocated_;         ///< the states with collocation rows
  std::vector<int> kept_initial_rows_;  ///< initial rows not already decided by fixed values
  std::vector<double> low_, high_;      ///< variable bounds
  /// Per point: every function of functions_ at the z of cached_.
  std::vector<std::vector<ValueGradient>> at_;
  std::vector<double> cached_;
  bool cached_derivatives_ = false;
  std::vector<std::pair<int, int>> hessian_entries_;  ///< (row, column), row >= column
  std::map<std::pair<int, int>, int> hessian_index_;
  std::vector<double> s_;       ///< per point its fraction of the horizon
  std::vector<double> weight_;  ///< per point its Simpson weight, in units of T - t0
};

}  // namespace nhc::optimize
