#pragma once
/// \file shell.hpp
/// \brief Shell quoting, for a command line shown in a message (the compiler's in
/// jit/compiler.cpp). nhc runs its programs (compilers, gnuplot) without a shell, through
/// tools/nhc/tools/subprocess.hpp.

#include <string>

namespace nhc {

/// Text in single quotes for /bin/sh.
std::string shell_quote(const std::string& s);

}  // namespace nhc
