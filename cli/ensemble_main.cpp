// nhc-ensemble: the commands that read and write HDF5 and run on MPI ranks (nhc ensemble, nhc
// plot), in a program of their own so that the others start without those libraries
// (command_programs.hpp).
#include "commands.hpp"
#include "program_main.hpp"

int main(int argc, char** argv) {
  return nhc::cli::run_program(argc, argv, {nhc::cli::add_ensemble_command, nhc::cli::add_plot_command});
}
