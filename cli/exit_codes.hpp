#pragma once
/// \file exit_codes.hpp
/// \brief The exit codes of the nhc command (README, "Command line"). The libraries report
/// failures as exceptions (nhc::InputError, nhc::MathError, nhc::EnvironmentError, nhc::base::SolverError); only
/// the command turns them into a process status.

namespace nhc::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
/// A bad scene (one line FILE:LINE:COLUMN: error: …) or a bad flag.
inline constexpr int kExitBadInput = 2;
/// A numerical or mathematical failure: a singular system, an integrator failure (with t).
inline constexpr int kExitMathFailure = 3;
/// The environment failed nhc (cannot write, disk full, compiler missing or failing, cannot load
/// a library, cache directory unusable): nhc::EnvironmentError.
inline constexpr int kExitEnvironment = 4;

}  // namespace nhc::cli
