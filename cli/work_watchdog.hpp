#pragma once
/// \file work_watchdog.hpp
/// \brief The backstop of the work budget on the command line: a thread that watches the
/// processor time spent in symbolic stages (nhc/expr/work_stage.hpp) and, past the limit, ends the
/// process as a refused input does: one line naming the scene file and the stage, temporary
/// files removed, exit 2. A GiNaC call cannot be interrupted from inside (no cancellation
/// points, and unwinding through it would leave its reference counts inconsistent), so ending
/// the process is the only sure stop; the Python module has no such thread (docs/intermediates.md).

namespace nhc::cli {

/// Processor seconds of symbolic work allowed (`--work-limit`; default kDefaultWorkSeconds).
extern double work_limit_seconds;
/// True once --work-limit was given: the user's limit holds as written.
extern bool work_limit_given;
/// True once --expand was given: substituting every definition multiplies the work (the Whipple
/// bicycle derives in 0.06 s with its definitions named, 4 s substituted), so the default limit
/// is kExpandedWorkFactor times larger for it.
extern bool work_expanded;
inline constexpr double kExpandedWorkFactor = 25.0;
/// The limit in force.
double work_limit();

/// Starts the watchdog thread (once; it runs until the process ends).
void start_work_watchdog();

}  // namespace nhc::cli
