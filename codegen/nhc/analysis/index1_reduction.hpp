#pragma once
/// \file index1_reduction.hpp
/// \brief The index-1 form of a model for IDA (models.md, "Structural analysis", step 5;
/// Pryce, BIT 41 (2001), §4; Nedialkov & Pryce, BIT 45 (2005)): each equation f_i is
/// differentiated c_i times with D; the states are x_j, …, x_j^(d_j−1) (x_j algebraic when
/// d_j = 0); the residuals are the D^{c_i} f_i and the chain rows; the D^r f_i, r < c_i, are
/// kept apart as hidden constraints. See index1_system.hpp for the exact layout.
///
/// The Jacobian of the D^{c_i} f_i with respect to the leading derivatives x_j^(d_j) is Pryce's
/// system Jacobian, so the reduced system is index 1 wherever that is nonsingular.

#include <vector>

#include "nhc/analysis/consistent_initialization.hpp"
#include "nhc/analysis/index1_system.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// Throws MathError when the model is not applicable or its system is structurally singular
/// (the message names the equations and unknowns).
Index1System reduce_to_index1(const Scene& scene, const DerivedModel& model);
/// Same, from the structure of an analysis already made (app::Preparation): the Σ-method is not
/// run again; the refusal names the scene as the overload above.
Index1System reduce_to_index1(const Scene& scene, const StructuralAnalysis& analysis);
/// Same, from an analysis already made.
Index1System reduce_to_index1(const StructuralAnalysis& analysis);

/// y(t0) and y'(t0) of the reduced system at a consistent point (y' of an algebraic
/// component is 0).
void initial_state(const Index1System& system, const ConsistentPoint& point, std::vector<double>& y0,
                   std::vector<double>& yp0);

}  // namespace nhc
