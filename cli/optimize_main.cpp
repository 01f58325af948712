// nhc-optimize: nhc optimize (IPOPT with Debian's sequential MUMPS, whose stand-ins for MPI_Init,
// MPI_Comm_rank, … must not meet Open MPI in one process), in a program of its own
// (command_programs.hpp).
// It runs `nhc simulate` too for a scene with model predictive control (mpc in [controller]),
// whose solves are IPOPT's: nhc-main starts this program for it (simulate_command.cpp).
#include "commands.hpp"
#include "nhc/app/mpc_controller.hpp"
#include "program_main.hpp"
#include "run_flags.hpp"

namespace {

nhc::cli::MpcParts make_mpc(const nhc::Scene& scene_set, const nhc::runtime::Model& model,
                            const std::vector<double>& samples) {
  auto controller = std::make_shared<nhc::app::MpcController>(scene_set, model, scene_set.controller.mpc);
  nhc::cli::MpcParts parts;
  parts.control = nhc::app::RunControl{nhc::app::sample_law(controller),
                                       controller->held(),
                                       samples,
                                       scene_set.controller.period,
                                       nullptr,
                                       [controller](bool at_sample) { return controller->column_values(at_sample); }};
  parts.columns = nhc::app::MpcController::columns();
  parts.summary = [controller] { return controller->summary(); };
  return parts;
}

}  // namespace

int main(int argc, char** argv) {
  nhc::cli::mpc_factory = make_mpc;
  return nhc::cli::run_program(argc, argv, {nhc::cli::add_optimize_command, nhc::cli::add_simulate_command});
}
