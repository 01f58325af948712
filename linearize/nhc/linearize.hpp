#pragma once
/// \file linearize.hpp
/// \brief nhc::linearize — linear stability of equilibria and steady motions of any model
/// (CMake target nhc::linearize; docs/linearize.md).
///
/// The operating point is the scene's [initial] with overrides, completed to a consistent point
/// of the model (consistent_initialization.hpp). Cyclic coordinates (the index-1 residual and
/// the hidden constraints depend only on their derivatives) are removed, so steady motions
/// become equilibria. The linear system is written in a minimal set of states: algebraic states
/// are solved from the residual, and the directions cut by the hidden constraints are
/// eliminated (one state per independent constraint). Zero eigenvalues whose eigenvectors are
/// tangent to a family of steady motions are named and counted apart from the others.
///
///   nhc::Scene scene = nhc::load_scene("disk.toml");
///   nhc::Linearization lin = nhc::linearize(scene, nhc::ModelKind::chetaev, {{"ps'", 6.0}});
///   Eigen::MatrixXd A = lin.A;            // d(δs)/dt = A δs, δs over lin.states
///
/// Failures: InputError for an override naming nothing in the scene (flag "--at"); MathError
/// for a point that is not stationary (naming the worst state), a model not applicable, a
/// singular system at the point or a residual that depends on t.

#include "nhc/linearize/linearization.hpp"
#include "nhc/linearize/linearizer.hpp"
#include "nhc/linearize/steady_families.hpp"
#include "nhc/linearize/operating_point.hpp"
#include "nhc/linearize/sweep.hpp"
