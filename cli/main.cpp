// nhc — the nonholonomic compiler: the program nhc-main, which runs every command but those of
// kCommandPrograms (command_programs.hpp): for these it starts their own program.
#include "commands.hpp"
#include "fixed_address_layout.hpp"
#include "program_main.hpp"

int main(int argc, char** argv) {
  using namespace nhc::cli;
  // Before starting another program, so that it inherits the fixed layout.
  run_with_fixed_address_layout(argv);
  if (argc > 1)
    if (const CommandProgram* entry = command_program(argv[1])) return start_command_program(*entry, argv);
  return run_program(
      argc, argv,
      {add_derive_command, add_analyze_command, add_generate_command, add_simulate_command, add_report_command,
       add_compare_command, add_connect_command, add_linearize_command, add_animate_command},
      /*list_external=*/true);
}
