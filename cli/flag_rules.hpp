#pragma once
/// \file flag_rules.hpp
/// \brief The rule for each kind of command-line flag, decided once and used by every command
/// that has the flag: tolerances, positive numbers, counts, lists of models. A value that breaks
/// a rule is bad input (exit 2) in the same words everywhere, naming the flag:
/// `nhc: error: --rtol: nan is not a positive number`.
///
/// CLI11's own PositiveNumber and Range let NaN through (every comparison with NaN is false)
/// and print their bounds in full (DBL_MAX in 309 digits); these do neither.

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "nhc/app/run_request.hpp"

namespace nhc::cli::flag_rules {

/// A finite number greater than 0 (--tolerance, --atol, --atol-scale, --checkpoint-every).
CLI::Validator positive();
/// A relative tolerance the arithmetic can honour: positive, finite, at least the machine
/// epsilon (nhc/scene/tolerances.hpp).
CLI::Validator relative_tolerance();
/// An absolute tolerance: a finite number greater than 0.
CLI::Validator absolute_tolerance();
/// A finite number (--t-end; whether it lies after t0 is the command's check, with the scene).
CLI::Validator finite();
/// A whole number from `low` to `high` (--outputs, --repeats, --segments, --max-iterations).
CLI::Validator count(long long low, long long high);
/// The largest number of output intervals any command writes (nhc/app/run_request.hpp).
inline constexpr long long kMaxOutputs = app::kMaxOutputs;
/// Each element of a list flag once (--models chetaev,chetaev would compare a model with
/// itself; --at x=1 --at x=2 would keep the last): InputError at `flag` otherwise. `keys` are
/// the elements, or the names of NAME=VALUE elements.
void refuse_duplicates(const std::vector<std::string>& keys, const std::string& flag, const std::string& what);

/// Every option of every subcommand of `app` that takes a value refuses an empty one
/// (`--output-times ''`, `-o ''` would otherwise act as if the flag were absent).
void refuse_empty_values(CLI::App& app);

/// The first argument written `--flag=` with nothing after the `=`, if any (before a lone `--`).
/// CLI11 would take the next argument as its value (`--t-end= -o out.csv` read `-o` as the time),
/// so the command refuses it before parsing, in the words of refuse_empty_values().
std::optional<std::string> empty_inline_value(int argc, const char* const* argv);
/// The message for an empty value, shared by both checks.
std::string empty_value_message();

/// Equally spaced output times from t0 to t_end, refused (InputError at `flags`) where
/// consecutive ones collapse in floating point instead of silently writing fewer rows.
std::vector<double> output_times(double t0, double t_end, long long intervals, const std::string& flags);

}  // namespace nhc::cli::flag_rules

namespace nhc::cli {

/// Adds `--set NAME=VALUE` to a subcommand, collecting into `assignments`; the rules of the values
/// it gives are app::parse_parameter_overrides (nhc/app/parameter_overrides.hpp).
inline void add_set_option(CLI::App* sub, std::vector<std::string>& assignments) {
  sub->add_option("--set", assignments, "NAME=VALUE: override a parameter of the scene (repeatable)");
}

}  // namespace nhc::cli
