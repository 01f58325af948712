#pragma once
/// \file transversal.hpp
/// \brief Highest-value transversal of a signature matrix: a one-to-one assignment
/// T of equations to unknowns maximising Σ_i σ_{i,T(i)} over finite entries (models.md,
/// "Structural analysis", step 2; Pryce, BIT 41 (2001), §3), found by the Hungarian method.
///
/// The assignment problem is solved on the bipartite graph of the finite entries by the
/// shortest-augmenting-path form of the Hungarian method with row and column potentials
/// (Kuhn 1955; Munkres 1957; Jonker & Volgenant 1987), each path found by Dijkstra's method
/// over the sparse rows and stopped at the first free column (Duff & Koster, SIAM J. Matrix
/// Anal. Appl. 22 (2001) 973–996): no n×n cost matrix is formed (docs/analysis.md). When no transversal of finite
/// entries exists the system is structurally singular; structural_deficiency() then names a set of equations that
/// involve too few unknowns (Hall's condition fails; Kőnig's theorem).

#include <optional>
#include <vector>

#include "nhc/analysis/signature_matrix.hpp"

namespace nhc {

struct Transversal {
  std::vector<int> column_of_row;  ///< T(i): the unknown assigned to equation i
  long long value = 0;             ///< Σ_i σ_{i,T(i)}
};

/// A highest-value transversal of a square σ, or nullopt when every transversal
/// contains a −∞ entry (structural singularity).
std::optional<Transversal> highest_value_transversal(const SignatureMatrix& sigma);

/// Witness of structural singularity: equations `rows` whose finite entries all lie in the
/// unknowns `cols`, with cols.size() < rows.size() (so they cannot all be solved for
/// distinct unknowns); `unmatched_cols` are unknowns no maximum matching can reach.
struct StructuralDeficiency {
  std::vector<int> rows;
  std::vector<int> cols;
  std::vector<int> unmatched_cols;
  int matching_size = 0;  ///< size of a maximum matching on finite entries (structural rank)
};

/// Computed from a maximum bipartite matching; empty rows when σ has a finite transversal.
StructuralDeficiency structural_deficiency(const SignatureMatrix& sigma);

}  // namespace nhc
