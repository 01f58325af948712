#pragma once
/// \file cyclic_reduction.hpp
/// \brief The index-1 system with its cyclic coordinates removed (docs/linearize.md, "Cyclic
/// coordinates"), and its residual and hidden constraints differentiated symbolically.
///
/// A coordinate q is cyclic when neither the index-1 residual F nor the hidden constraints g
/// contain the state q itself (only q', q'', …). Then the state q and its chain row
/// q' − y[q'] = 0 are dropped (d_q ≥ 2); for d_q = 1 the state q is dropped and q' (which the
/// residual holds as the derivative of q) becomes an algebraic state. Steady motions with
/// constant q' are then equilibria of what remains. A cyclic coordinate named in `keep` stays a
/// state (with its chain row): a controller that must hold a position needs it (docs/linearize.md,
/// "Choosing the states").

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/analysis/index1_system.hpp"

namespace nhc {

/// One state z_c of the reduced system.
struct ReducedComponent {
  GiNaC::ex value;       ///< its symbol (a y[k], or yp[k] for the q' of a cyclic q with d_q = 1)
  GiNaC::ex derivative;  ///< the symbol of z_c' (yp[k]); 0 when algebraic
  bool differential = true;
  std::string name;
  int order = 0;  ///< derivative order of the variable it holds
  bool multiplier = false;
};

struct CyclicReduction {
  std::vector<std::string> cyclic;           ///< removed coordinates
  std::vector<std::string> kept;             ///< cyclic coordinates kept as states (`keep`)
  std::vector<ReducedComponent> components;  ///< z, N of them
  std::vector<GiNaC::ex> residuals;          ///< F(p, z, z'), N of them
  std::vector<std::string> residual_names;
  std::vector<GiNaC::ex> hidden;  ///< g(p, z)
  std::vector<std::string> hidden_names;
  std::vector<std::vector<GiNaC::ex>> dF_dz, dF_dzp;  ///< N × N
  std::vector<std::vector<GiNaC::ex>> dg_dz;          ///< m × N
};

/// MathError when the residual or a hidden constraint depends on t explicitly.
void require_autonomous(const Index1System& system, const GiNaC::ex& time);

/// With `autonomous`, throws MathError when the residual or a hidden constraint depends on t
/// explicitly (a non-autonomous system has no equilibria to linearize about); a linearization
/// along a motion takes such a system.
CyclicReduction reduce_cyclic(const Index1System& system, const GiNaC::ex& time,
                              const std::vector<std::string>& keep = {}, bool autonomous = true);

}  // namespace nhc
