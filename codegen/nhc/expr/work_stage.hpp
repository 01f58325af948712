#pragma once
/// \file work_stage.hpp
/// \brief The clock of the symbolic work: processor time spent inside the symbolic stages
/// (deriving, reducing to index 1, Jacobians, CSE, printing), the stage running now, and the
/// limit the command line's watchdog holds it to (cli/work_watchdog.hpp). Predictions
/// (work_budget.hpp) refuse most runaway expansions before they start; this clock is the
/// backstop for work no prediction saw, since one GiNaC call cannot be interrupted from inside.
/// Why a watchdog rather than a worker process: docs/intermediates.md, "The work budget".

#include <string>

namespace nhc::work_budget {

/// How much slower this build does the same work than a Release build: the sanitizer build
/// (scripts/sanitize.sh, ASan + UBSan at -O1) runs the symbolic stages 5–10 times slower, and its
/// default limit is scaled so that it refuses the same scenes as the Release build.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr double kBuildSlowdown = 10.0;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr double kBuildSlowdown = 10.0;
#else
inline constexpr double kBuildSlowdown = 1.0;
#endif
#else
inline constexpr double kBuildSlowdown = 1.0;
#endif

/// Processor seconds of symbolic work a command may spend by default (`--work-limit` raises it).
/// The examples need at most 0.3 s, the 1024-body knife chain about 1.5 s (Release).
inline constexpr double kDefaultWorkSeconds = 4.0 * kBuildSlowdown;

/// Marks a symbolic stage for the lifetime of the object; stages nest (the innermost is named).
/// Not a lock: cheap, and a no-op for the clock when no watchdog runs.
class Stage {
 public:
  explicit Stage(const char* name);
  ~Stage();
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;

 private:
  const char* outer_;
};

/// The scene whose work is being measured (for the watchdog's message); "" when none.
void set_scene_path(const std::string& path);

/// What the watchdog reads: the innermost stage (nullptr outside every stage), the processor
/// seconds spent inside stages so far, and the scene path. Safe to call from another thread.
struct StageSnapshot {
  const char* stage = nullptr;
  double seconds = 0;
  const char* scene_path = "";
};
StageSnapshot stage_snapshot();

/// The same budget asked for cooperatively, for callers that cannot end their process (the
/// Python module): the stop question of long work (nhc/long_work.hpp) asks exceeded(), which is
/// true once the symbolic stages have spent more than `seconds` of processor time since this was
/// made. The work then stops at its next question (between two GiNaC calls: the predictions of
/// work_budget.hpp keep each call short), where the command line's watchdog would end the process.
class ProcessorTimeLimit {
 public:
  explicit ProcessorTimeLimit(double seconds);
  /// True once exceeded (and from then on); remembers the stage and the scene.
  bool exceeded();
  /// "STAGE took more than S s of processor time: the expressions grow too large (HOW_TO_RAISE)",
  /// the command line's words (an error at scene_path()); after exceeded().
  std::string message(const std::string& how_to_raise) const;
  /// The scene file of the refused work ("" when none).
  const std::string& scene_path() const { return scene_; }

 private:
  double seconds_;
  double start_;
  bool exceeded_ = false;
  std::string stage_, scene_;
};

}  // namespace nhc::work_budget
