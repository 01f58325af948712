#pragma once
/// \file fixed_address_layout.hpp
/// \brief The same header from every run of one scene, whatever the process's address layout.
///
/// GiNaC orders the terms of sums and products, and so decides how expansion, common
/// denominators and sin² + cos² = 1 come out, by hash values seeded with the addresses of C++
/// type information. With address-space layout randomization those addresses, and so the
/// generated code, change from run to run: the Whipple bicycle's header had 15,478 to 15,762
/// operations after CSE in four runs, each a different file that compiles anew. The printers
/// already order what they print by content (expression_printer.hpp, expr/expression_dag.hpp); the
/// symbolic work itself cannot be, so the command line runs once more without randomization,
/// as `setarch -R` does.

namespace nhc::cli {

/// Re-executes this program (/proc/self/exe, same arguments and environment) with address
/// randomization off, unless it is already off. Where the system refuses (a seccomp filter, no
/// /proc), returns and the run goes on with randomization: the results are right, only the
/// term order may differ between runs.
void run_with_fixed_address_layout(char** argv);

}  // namespace nhc::cli
