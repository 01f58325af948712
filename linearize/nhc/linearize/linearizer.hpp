#pragma once
/// \file linearizer.hpp
/// \brief Linearization of one model of a scene at operating points (docs/linearize.md).
///
/// Construction derives the model, reduces it to index 1, detects the cyclic coordinates and
/// differentiates the reduced residual and hidden constraints symbolically once; at() then
/// evaluates at a point, so a sweep pays for the symbolic work only once.

#include <memory>
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

  const Scene& scene() const;
  ModelKind model() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot form: Linearizer(scene, model, options).at(overrides).
Linearization linearize(const Scene& scene, ModelKind model,
                        const std::vector<PointOverride>& overrides = {},
                        const LinearizeOptions& options = {});

}  // namespace nhc
