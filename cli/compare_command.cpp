#include "commands.hpp"
namespace nhc::cli {
CommandRunner add_compare_command(CLI::App& app) {
  app.add_subcommand("compare", "x");
  return [] { return 0; };
}
}  // namespace nhc::cli
