#pragma once
/// \file command_programs.hpp
/// \brief The commands that run in programs of their own, beside nhc-main: `ensemble` and `plot`
/// (HDF5, Open MPI) in nhc-ensemble, `optimize` (IPOPT, MUMPS) in nhc-optimize. The launcher
/// (launcher.cpp) and nhc-main both start the right program from this one table, so that the
/// other commands load neither library family (docs/architecture.md, "Programs").
/// Light enough for the launcher, which includes it.

#include <unistd.h>

#include <climits>
#include <cstring>
#include <string>

namespace nhc::cli {

struct CommandProgram {
  const char* command;      ///< the subcommand, argv[1]
  const char* program;      ///< the program that runs it, beside nhc-main
  const char* description;  ///< its line in `nhc --help`
};

inline constexpr CommandProgram kCommandPrograms[] = {
    {"ensemble", "nhc-ensemble",
     "many runs of one model over a grid or a random sample of parameters and initial values "
     "(threads, or MPI ranks under mpirun), results in HDF5"},
    {"plot", "nhc-ensemble", "a map of an outcome of an ensemble (FILE.h5 of nhc ensemble)"},
    {"optimize", "nhc-optimize",
     "an optimal motion of a scene's [optimize] problem (Hermite-Simpson collocation, IPOPT)"},
};

/// The entry of `command`, or nullptr when nhc-main runs it.
inline const CommandProgram* command_program(const char* command) {
  if (command == nullptr) return nullptr;
  for (const CommandProgram& entry : kCommandPrograms)
    if (std::strcmp(entry.command, command) == 0) return &entry;
  return nullptr;
}

/// The directory of the running program, from /proc/self/exe ("" when unknown): where the
/// launcher finds nhc-main and nhc-main the programs of this table.
inline std::string own_directory() {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return "";
  path[n] = '\0';
  const std::string p(path);
  const std::size_t slash = p.rfind('/');
  return slash == std::string::npos ? "" : p.substr(0, slash);
}

/// The description of a command of kCommandPrograms (for its program's add_*_command).
inline const char* command_description(const char* command) {
  const CommandProgram* entry = command_program(command);
  return entry ? entry->description : "";
}

}  // namespace nhc::cli
