#pragma once
/// \file shell.hpp
/// \brief Shell quoting (for a command line shown in a message, as the compiler's in
/// jit/compiler.cpp) and a shell runner for tests. nhc runs its programs (compilers, gnuplot)
/// without a shell, through tools/nhc/tools/subprocess.hpp.

#include <string>

namespace nhc {

/// Text in single quotes for /bin/sh.
std::string shell_quote(const std::string& s);

/// Runs a shell command; returns its exit status (-1 when it could not run or was killed) and
/// appends its stdout and stderr to `output`.
int run_command(const std::string& command, std::string& output);

}  // namespace nhc
