#include "work_watchdog.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "exit_codes.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/expr/work_stage.hpp"

namespace nhc::cli {

double work_limit_seconds = work_budget::kDefaultWorkSeconds;
bool work_limit_given = false;
bool work_expanded = false;

double work_limit() {
  return work_limit_given || !work_expanded ? work_limit_seconds : work_limit_seconds * kExpandedWorkFactor;
}

namespace {

[[noreturn]] void refuse(const work_budget::StageSnapshot& s) {
  nhc::cleanup_after_signal();
  char line[1024];
  const int n = std::snprintf(line, sizeof line,
                              "%s: error: %s took more than %g s of processor time: the expressions grow too "
                              "large (raise the limit with --work-limit SECONDS)\n",
                              *s.scene_path != '\0' ? s.scene_path : "nhc", s.stage, work_limit());
  if (n > 0) (void)!::write(STDERR_FILENO, line, static_cast<std::size_t>(n) < sizeof line ? n : sizeof line - 1);
  ::_exit(kExitBadInput);
}

}  // namespace

void start_work_watchdog() {
  static bool started = false;
  if (started) return;
  started = true;
  std::thread([] {
    for (;;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      const work_budget::StageSnapshot s = work_budget::stage_snapshot();
      if (s.stage != nullptr && s.seconds > work_limit()) refuse(s);
    }
  }).detach();
}

}  // namespace nhc::cli
