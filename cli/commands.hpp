#pragma once
/// \file commands.hpp
/// \brief The nhc subcommands. Each add_*_command registers its flags on the CLI11 app and
/// returns the function that runs it after parsing; the function returns the exit code and
/// may throw nhc::InputError (exit 2) or nhc::MathError (exit 3).

#include <CLI/CLI.hpp>

#include <functional>

#include "exit_codes.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

using CommandRunner = std::function<int()>;

CommandRunner add_derive_command(CLI::App& app);
CommandRunner add_analyze_command(CLI::App& app);
CommandRunner add_generate_command(CLI::App& app);
CommandRunner add_simulate_command(CLI::App& app);
CommandRunner add_report_command(CLI::App& app);
CommandRunner add_compare_command(CLI::App& app);
CommandRunner add_ensemble_command(CLI::App& app);
CommandRunner add_plot_command(CLI::App& app);
CommandRunner add_connect_command(CLI::App& app);
CommandRunner add_optimize_command(CLI::App& app);
CommandRunner add_linearize_command(CLI::App& app);
CommandRunner add_animate_command(CLI::App& app);

/// `--expand`: read the scene with every definition substituted (SceneOptions), the fully
/// expanded equations; by default definitions stay named intermediates (docs/intermediates.md).
void add_expand_flag(CLI::App* sub, SceneOptions& options);
/// `--work-limit SECONDS`: the processor time the symbolic stages may take (work_watchdog.hpp).
void add_work_limit_flag(CLI::App* sub);

/// The scene's models, or those named by --model flags.
std::vector<ModelKind> selected_models(const Scene& scene, const std::vector<std::string>& names);

}  // namespace nhc::cli
