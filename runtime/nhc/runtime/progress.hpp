#pragma once
/// \file progress.hpp
/// \brief Where a run stands, reported to a callback its caller owns: the runtime draws nothing
/// on the caller's terminal (`nhc simulate` turns the reports into a bar on stderr,
/// cli/progress_bar.hpp).

#include <functional>

namespace nhc::runtime {

struct Progress {
  double t_start = 0;     ///< where this integrate() call started
  double t = 0;           ///< the last accepted step
  double t_end = 0;       ///< the last output time asked for
  bool finished = false;  ///< the call returned or failed; the last report of the call
};

/// Called at the start of each integrate(), after every accepted step, and once finished.
using ProgressCallback = std::function<void(const Progress&)>;

/// The reports of one integrate() call; `finished` also when it leaves by an exception.
class ProgressReporter {
 public:
  ProgressReporter(const ProgressCallback& callback, double t_start, double t_end)
      : callback_(callback), report_{t_start, t_start, t_end, false} {
    if (callback_) callback_(report_);
  }
  ~ProgressReporter() { finish(); }
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  void update(double t) {
    if (!callback_ || report_.finished) return;
    report_.t = t;
    callback_(report_);
  }
  void finish() {
    if (!callback_ || report_.finished) return;
    report_.finished = true;
    callback_(report_);
  }

 private:
  const ProgressCallback& callback_;
  Progress report_;
};

}  // namespace nhc::runtime
