#pragma once
/// \file shell.hpp
/// \brief Running shell commands with their output captured (gnuplot, compilers in tools and
/// benchmarks). Commands that an interrupt must be able to stop use jit/nhc/jit/subprocess.hpp instead.

#include <string>

namespace nhc {

/// Text in single quotes for /bin/sh.
std::string shell_quote(const std::string& s);

/// Runs a shell command; returns its exit status (-1 when it could not run or was killed) and
/// appends its stdout and stderr to `output`.
int run_command(const std::string& command, std::string& output);

}  // namespace nhc
