#pragma once
/// \file parameter_overrides.hpp
/// \brief `--set NAME=VALUE` (repeatable), one helper for derive, analyze, generate, simulate and
/// report: a scene parameter replaced by a value from the command line (the flag itself:
/// add_set_option in cli/flag_rules.hpp). Bad assignments and unknown names are bad input naming the
/// flag (exit 2).

#include <string>
#include <utility>
#include <vector>

#include "nhc/runtime/model.hpp"
#include "nhc/runtime/sensitivity.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

struct ParameterOverride {
  std::string name;
  double value = 0;
};

/// "NAME=VALUE" → (NAME, VALUE); VALUE kept as text. InputError naming `flag` otherwise.
std::pair<std::string, std::string> split_assignment(const std::string& flag, const std::string& text);
/// A finite number, all of `text`; InputError at `flag` otherwise, quoting `written` (the whole
/// assignment) when given.
double parse_number(const std::string& flag, const std::string& text, const std::string& written = "");

/// The assignments checked against the scene's [parameters] (the last of repeated names wins).
std::vector<ParameterOverride> parse_parameter_overrides(const Scene& scene,
                                                         const std::vector<std::string>& assignments);

/// The scene with its parameter values replaced (derivation, analysis and generated defaults),
/// and its [initial] values written through parameters re-evaluated.
void apply_parameter_overrides(Scene& scene, const std::vector<ParameterOverride>& overrides);

/// The model's default parameters with the overrides (a compiled model reused for any value).
/// An override of a scene parameter the model does not read (it occurs in no equation,
/// invariant or reference, so it does not reach the header) changes nothing there and is
/// skipped; apply_parameter_overrides() has given it to the scene for its outputs.
std::vector<double> parameters_with_overrides(const runtime::Model& model,
                                              const std::vector<ParameterOverride>& overrides);

/// InputError at `flag` when `name` is a parameter of the scene that `model` does not read:
/// varying it, or differentiating with respect to it, would change nothing. `consequence`
/// says so in the flag's terms ("varying it would change nothing"); where a contact's mu, the
/// controller's period or [simulate] is written through it, the words name that place. A
/// parameter the scene's [initial] is written through moves the start: the callers take it
/// (initial_slopes()) before asking.
void refuse_unread_parameter(const Scene& scene, const runtime::Model& model, const std::string& name,
                             const std::string& flag, const std::string& consequence);

/// The quantities `--sensitivity NAMES` (Python: sensitivity=) differentiates by: a parameter of
/// the model, an initial value x(0), x'(0), or a parameter only [initial] is written through
/// (runtime::SensitivityParameter::Kind::start); a parameter's initial_slope is ∂y(t0)/∂θ of the
/// given values written through it (initial_slopes()), so that s(t0) differentiates the start
/// as well. InputError at `flag` in words otherwise (an unknown name, one named twice, a
/// parameter nothing the run follows reads).
std::vector<runtime::SensitivityParameter> sensitivity_parameters(const Scene& scene, const runtime::Model& model,
                                                                  const std::vector<std::string>& names,
                                                                  const std::string& flag);

}  // namespace nhc::app
