#pragma once
/// \file interrupt.hpp
/// \brief SIGINT / SIGTERM / SIGHUP handling of the nhc command: an interrupted run stops the
/// child processes it started (the compiler of `nhc simulate`), removes its registered temporary
/// files (nhc/io/temporary_files.hpp) and exits with 128 + the signal number (130 for SIGINT),
/// so that no partial output or cache entry is ever left behind.

namespace nhc::cli {

void install_interrupt_handlers();

}  // namespace nhc::cli
