#pragma once
/// \file linearizer.hpp
/// \brief Linearization of one model of a scene at operating points (docs/linearize.md).
///
/// Construction derives the model, reduces it to index 1, detects the cyclic coordinates and
/// differentiates the reduced residual and hidden constraints symbolically once; at() then
/// evaluates at a point, so a sweep pays for the symbolic work only once.

#include <Eigen/Dense>

#include <memory>
#include <string>
#include <vector>

#include "nhc/linearize/linearization.hpp"
#include "nhc/linearize/operating_point.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct LinearizeOptions {
  /// Eigenvalues with |Re λ| ≤ tolerance·max(1, ‖A‖) lie on the imaginary axis.
  double tolerance = 1e-9;
  /// Eigenvalues with |λ| ≤ zero_tolerance·max(1, ‖A‖) are zero (a defective zero eigenvalue
  /// of multiplicity k is perturbed by rounding to about ε^(1/k)).
  double zero_tolerance = 1e-6;
  /// A point is stationary when max |s'| ≤ stationarity·(1 + max |state|).
  double stationarity = 1e-8;
  /// Cyclic coordinates kept as states (`--keep x,y`): not removed, and exempt from the
  /// stationarity check (the equations do not contain them, so a steady drift of one is a steady
  /// motion). Names that are no coordinate of the scene: InputError at "--keep".
  std::vector<std::string> keep;
  /// The reduced states wanted, in this order (`--states th,th',x,x'`): never eliminated by the
  /// hidden constraints, and A, B, C over them in this order. InputError at "--states" for a name
  /// that is no differential state of the reduced system, or a set that is not the whole state
  /// (docs/linearize.md, "Choosing the states").
  std::vector<std::string> states;
  /// A relative equilibrium of the rotations of a plane (`--turn psi:x,y`): turning by c adds c
  /// to `angle` and rotates every derivative of (`x`, `y`) by c. The operating point is a steady
  /// turn at ω = angle' there: stationary in the turning frame (z' = ω X(z), X the generator), the
  /// equations checked invariant under the turn, and A the linearization in the turning frame,
  /// A − ω DX (docs/linearize.md, "Relative equilibria"). Empty `angle`: none.
  struct Turn {
    std::string angle, x, y;
  } turn;
};

class Linearizer {
 public:
  /// Throws MathError when the model is not applicable, structurally singular, or its residual
  /// depends on t explicitly.
  Linearizer(const Scene& scene, ModelKind model, LinearizeOptions options = {});
  ~Linearizer();
  Linearizer(Linearizer&&) noexcept;
  Linearizer& operator=(Linearizer&&) noexcept;

  /// The linearization at the scene's [initial] with `overrides` applied (in order).
  /// Throws InputError for an unknown override name, MathError for a point that is not
  /// stationary or a singular system there.
  Linearization at(const std::vector<PointOverride>& overrides = {}) const;
  const LinearizeOptions& options() const;

  /// The linearization along a motion, at one of its points (docs/linearize.md, "Along a
  /// motion"): d(δs)/dt = A(t) δs + B(t) δu on the same reduced states as at(), at the index-1
  /// state y, y' (Index1System order, which is the generated model's) with inputs u, parameters
  /// at the scene's values. No stationarity is asked and t may appear in the equations. Only
  /// states, inputs, A, B and basis are filled. Throws MathError for a singular system there.
  Linearization along(double t, const std::vector<double>& y, const std::vector<double>& yp,
                      const std::vector<double>& u) const;
  /// ∂F/∂u of the index-1 residual F(t, p, y, y', u) at a point (rows: residuals, columns:
  /// the scene's inputs), in exact derivatives evaluated in doubles.
  Eigen::MatrixXd input_jacobian(double t, const std::vector<double>& y, const std::vector<double>& yp,
                                 const std::vector<double>& u) const;
  /// The index-1 system's state names, in the order along() and input_jacobian() take y.
  std::vector<std::string> index1_states() const;

  const Scene& scene() const;
  ModelKind model() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// "psi:x,y" (`--turn`): InputError at `flag` unless it is ANGLE:X,Y.
LinearizeOptions::Turn parse_turn(const std::string& text, const std::string& flag = "--turn");

/// One-shot form: Linearizer(scene, model, options).at(overrides).
Linearization linearize(const Scene& scene, ModelKind model, const std::vector<PointOverride>& overrides = {},
                        const LinearizeOptions& options = {});

}  // namespace nhc
