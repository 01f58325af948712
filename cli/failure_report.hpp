#pragma once
/// \file failure_report.hpp
/// \brief The one place where a failure becomes words on standard error and an exit code
/// (exit_codes.hpp): bad input 2, mathematics 3, the environment 4 (a resource the machine
/// refuses included: memory, a thread, a file descriptor), anything else 1, "a bug in nhc".

#include <exception>

namespace nhc::cli {

/// Prints what `failure` says in the command's words and returns its exit code.
int report_failure(std::exception_ptr failure);

}  // namespace nhc::cli
