#pragma once
/// \file path_error.hpp
/// \brief How well a transcribed path solves the continuous problem between its points
/// (docs/optimize.md, "Path error"): with [inputs], the optimal inputs (the transcription's own
/// interpolant, the quadratic through each interval's three points) replayed by IDA from the
/// optimal initial state; without inputs, the constraints and bounds at the quarter points of
/// every interval's Hermite cubic. Both are measured in units of the states' scale.

#include <string>
#include <vector>

#include "nhc/optimize/hermite_simpson.hpp"

namespace nhc::optimize {

struct PathError {
  /// The path error E: with [inputs], the largest |y_IDA(t_k) - y_k| / scale_i over the mesh
  /// nodes and the differential states (scale_i = max(1, max_k |y_i,k|)) of the replay from t0,
  /// or the sum of the local errors below when that is smaller (a motion that amplifies small
  /// differences: docs/optimize.md, "Path error"); without inputs, the largest local error below.
  double error = 0;
  /// Per interval, its local error: with [inputs], IDA from the interval's first node to its
  /// last against the path's last node (scaled as above); without inputs, the largest violation
  /// of a constraint or a bounded quantity at the interval's quarter points times the interval's
  /// length (a rate's defect over the interval), or of a state's bound there, over the scale.
  std::vector<double> local;
  int interval = 0;              ///< the interval where the local error is largest
  double t_low = 0, t_high = 0;  ///< its ends
  std::string measure;           ///< "replay by IDA" or "quarter-point residuals"
  std::string where;             ///< in words: what is largest there ("the constraint … at t = 0.3")
  /// With [inputs]: the replay from t0's largest deviation (at replay_at), the sum of the local
  /// errors, and why the replay stopped (empty: it did not).
  double replay = 0, replay_at = 0, local_sum = 0;
  std::string replay_failure;
};

/// MathError when IDA cannot replay the inputs (a replay that fails is a path error too large to
/// measure: the caller reports it as such).
PathError path_error(HermiteSimpson& problem, const std::vector<double>& z);

}  // namespace nhc::optimize

namespace nhc::optimize {

/// The slots (y, y', u) of the transcription's interpolant at fraction `fraction` of the horizon.
std::vector<double> point_at(const HermiteSimpson& problem, const double* z, double fraction);
/// A path of `from` carried onto the points of `to` (same problem, another mesh) through the
/// interpolant: the warm start of a refined mesh. Clamped into `to`'s bounds.
std::vector<double> transfer(const HermiteSimpson& from, const std::vector<double>& z, const HermiteSimpson& to);

}  // namespace nhc::optimize
