#pragma once
/// \file linearization.hpp
/// \brief The result of linearizing a model at an operating point (docs/linearize.md).

#include <Eigen/Dense>

#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "nhc/scene/model_kind.hpp"

namespace nhc {

enum class StabilityVerdict { unstable, marginally_stable, asymptotically_stable };
/// "unstable", "marginally_stable", "asymptotically_stable".
std::string to_string(StabilityVerdict verdict);

/// A zero eigenvalue whose eigenvector is tangent to a family of steady motions.
struct SteadyFamily {
  std::vector<double> direction;  ///< unit kernel vector of A over Linearization::states
  std::string description;        ///< "family of steady motions along 0.71 th + 0.71 ph'"
};

struct Linearization {
  std::string scene;
  ModelKind model = ModelKind::chetaev;
  /// The operating point: parameters, then every state of the index-1 system (values of the
  /// consistent point), name → value.
  std::vector<std::pair<std::string, double>> point;
  /// Coordinates removed as cyclic.
  std::vector<std::string> cyclic;
  /// Cyclic coordinates kept as states (LinearizeOptions::keep).
  std::vector<std::string> kept;
  /// About a relative equilibrium (LinearizeOptions::turn): the turning rate ω, A and the
  /// defect in the turning frame; 0 otherwise.
  double turn_rate = 0.0;
  /// Reduced state names (the s of d(δs)/dt = A δs).
  std::vector<std::string> states;
  /// States eliminated by the hidden constraints (dependent on `states`), and the algebraic
  /// states solved from the residual.
  std::vector<std::string> eliminated, algebraic;
  /// How the basis was chosen, in words.
  std::string basis;
  Eigen::MatrixXd A;
  /// The scene's inputs ([inputs]) and d(δs)/dt = A δs + B δu: one column per input, rows over
  /// `states`; the operating point holds each input at its default signal's value at t0.
  std::vector<std::string> inputs;
  Eigen::MatrixXd B;
  /// The scene's [outputs] the model computes from the reduced states, and δh = C δs + D δu: a row
  /// per output (an output of a removed cyclic coordinate, or of something the model does not
  /// compute, is left out with a note).
  std::vector<std::string> outputs;
  Eigen::MatrixXd C, D;
  /// Sorted by real part, largest first, then by imaginary part.
  std::vector<std::complex<double>> eigenvalues;
  /// Eigenvalues counted as zero (|λ| ≤ zero tolerance), and the families of steady motions
  /// found among their eigenvectors (each explains one zero eigenvalue).
  int zero_eigenvalues = 0;
  std::vector<SteadyFamily> families;
  StabilityVerdict verdict = StabilityVerdict::marginally_stable;
  /// Largest |s'| at the point, relative to 1 + max |state|, and the state where it occurs.
  double defect = 0.0;
  std::string worst_state;
  /// Largest |Ĝ A| entry: how well the hidden constraints stay satisfied by the linear flow
  /// (should be at rounding level).
  double manifold_residual = 0.0;
  std::vector<std::string> notes;
};

}  // namespace nhc
