#pragma once
/// \file offsets.hpp
/// \brief Pryce's canonical offsets: the smallest c_i ≥ 0, d_j with d_j − c_i ≥ σ_ij for all
/// finite σ_ij and equality on a highest-value transversal (models.md, "Structural analysis",
/// step 3; Pryce, BIT 41 (2001) 364–394, §3.3, the fixed-point iteration of Alg. 3.1).
///
/// Starting from c = 0, the iteration alternates d_j = max_i (σ_ij + c_i) and
/// c_i = d_{T(i)} − σ_{i,T(i)}; it terminates, and its limit is the elementwise smallest
/// solution of the dual of the assignment problem (Pryce 2001, Thm. 3.6). The result does not
/// depend on which highest-value transversal is used.

#include <vector>

#include "nhc/analysis/signature_matrix.hpp"
#include "nhc/analysis/transversal.hpp"

namespace nhc {

struct Offsets {
  std::vector<int> c;  ///< per equation: how often it is differentiated
  std::vector<int> d;  ///< per unknown: the highest order in which it occurs after that
};

Offsets pryce_offsets(const SignatureMatrix& sigma, const Transversal& transversal);

}  // namespace nhc
