#pragma once
/// \file subprocess.hpp
/// \brief Running a helper program (the C++ compiler) without a shell, in a process group of its
/// own that the interrupt handler (interrupt.hpp) terminates, so that an interrupted nhc leaves
/// no compiler behind still writing into the cache.

#include <string>
#include <vector>

namespace nhc::jit {

/// Runs `argv[0]` (looked up in PATH) with `argv`; appends its standard output and error to
/// `output`. Returns its exit status, or -1 when it could not be started or was killed by a
/// signal.
int run_process(const std::vector<std::string>& argv, std::string& output);

}  // namespace nhc::jit
