#pragma once
/// \file program_main.hpp
/// \brief What every nhc program does around its commands (nhc-main, nhc-ensemble,
/// nhc-optimize): the fixed address layout, out-of-memory in words, interrupts, the work
/// watchdog, parsing with the project's flag messages and exit codes, failures as exit codes.

#include "command_programs.hpp"
#include "commands.hpp"

namespace nhc::cli {

using CommandAdder = CommandRunner (*)(CLI::App&);

/// Runs the program whose commands are `adders`; with `list_external`, `--help` also lists the
/// commands of the other programs (kCommandPrograms). Returns the exit code.
int run_program(int argc, char** argv, std::initializer_list<CommandAdder> adders, bool list_external = false);

/// The arguments run_program was started with (its argv): for start_command_program from inside
/// a command (nhc simulate of a scene with model predictive control starts nhc-optimize).
char** program_arguments();

/// Replaces this process by the program of `entry` (beside this one), with the same arguments;
/// returns exit 4 in words when it cannot be started.
int start_command_program(const CommandProgram& entry, char** argv);

}  // namespace nhc::cli
