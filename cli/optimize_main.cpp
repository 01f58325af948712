// nhc-optimize: nhc optimize (IPOPT with Debian's sequential MUMPS, whose stand-ins for MPI_Init,
// MPI_Comm_rank, … must not meet Open MPI in one process), in a program of its own
// (command_programs.hpp).
#include "commands.hpp"
#include "program_main.hpp"

int main(int argc, char** argv) { return nhc::cli::run_program(argc, argv, {nhc::cli::add_optimize_command}); }
