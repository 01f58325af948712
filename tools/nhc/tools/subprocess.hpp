#pragma once
/// \file subprocess.hpp
/// \brief Running a helper program (the C++ compiler) without a shell, in a process group of its
/// own that the interrupt handler (interrupt.hpp) terminates, so that an interrupted nhc leaves
/// no compiler behind still writing into the cache.

#include <string>
#include <vector>

namespace nhc::tools {

/// How a helper program ended.
struct ProcessResult {
  bool started = false;     ///< false: it could not be started; start_error says why
  std::string start_error;  ///< the system's reason (e.g. "No such file or directory")
  int exit_status = -1;     ///< its exit status when it exited
  int signal = 0;           ///< the signal that ended it, else 0
  bool timed_out = false;   ///< stopped by nhc after the time limit
  bool ok() const noexcept { return started && !timed_out && signal == 0 && exit_status == 0; }
};

/// Runs `argv[0]` (looked up in PATH) with `argv`; appends its standard output and error to
/// `output`. With `timeout_seconds` > 0 the whole process group is terminated (SIGTERM, then
/// SIGKILL two seconds later) when it runs longer.
ProcessResult run_process(const std::vector<std::string>& argv, std::string& output, double timeout_seconds);

/// As above without a time limit. Returns its exit status, or -1 when it could not be started or
/// was killed by a signal.
int run_process(const std::vector<std::string>& argv, std::string& output);

}  // namespace nhc::tools
