#pragma once
/// \file progress_bar.hpp
/// \brief A one-line progress bar on stderr, drawn only when stderr is a terminal and only once a
/// run has taken more than a second; erased when done. terminal_progress() draws one for the
/// runtime's progress reports (runtime/progress.hpp).

#include <chrono>

#include "nhc/runtime/progress.hpp"

namespace nhc::cli {

class ProgressBar {
 public:
  /// enabled = false: never draws. Otherwise draws when isatty(stderr).
  ProgressBar(double t0, double t1, bool enabled);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Cheap to call every step: redraws at most ten times a second.
  void update(double t);
  /// Erases the bar (also done by the destructor).
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  double t0_, t1_;
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_, last_draw_;
};

/// A progress callback that draws a ProgressBar for each integrate() call of a run (IDA's or the
/// variational integrator's), from its start report to its finished one.
runtime::ProgressCallback terminal_progress();

}  // namespace nhc::cli
