#pragma once
/// \file parameter_overrides.hpp
/// \brief The `--set NAME=VALUE` flag; the rules of the values it gives live in app/
/// (nhc/app/parameter_overrides.hpp).

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "nhc/app/parameter_overrides.hpp"

namespace nhc::cli {

using app::apply_parameter_overrides;
using app::parameters_with_overrides;
using app::ParameterOverride;
using app::parse_number;
using app::parse_parameter_overrides;
using app::refuse_unread_parameter;
using app::split_assignment;

/// Adds `--set NAME=VALUE` to a subcommand, collecting into `assignments`.
inline void add_set_option(CLI::App* sub, std::vector<std::string>& assignments) {
  sub->add_option("--set", assignments, "NAME=VALUE: override a parameter of the scene (repeatable)");
}

}  // namespace nhc::cli
