#pragma once
/// \file scene_builder.hpp
/// \brief Building a scene in code, for applications that use nhc as a library (nhc::codegen):
/// the same keys as a scene file (README.md, "Scenes"), set by method calls.
///
/// build() writes the equivalent scene file (toml()) and reads it with parse_scene(), so a
/// scene built in code is validated exactly like one read from disk, and every problem is an
/// InputError whose FILE:LINE:COLUMN points into toml(), under the name
/// `<name> (built in code)`. The scene's source_path is then "" (generated headers say
/// "a scene built in code").
///
/// \code
/// nhc::Scene scene = nhc::SceneBuilder("cart")
///     .coordinates({"x", "y"})
///     .parameter("m", 2.0)
///     .lagrangian("m/2*(x'^2 + y'^2)")
///     .constraint("y' - x'")
///     .initial("x", {0.0, 1.0})
///     .initial("y", {0.0})
///     .build();
/// \endcode

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/scene/scene.hpp"

namespace nhc {

class SceneBuilder {
 public:
  /// `name` becomes a C++ identifier and a file name (`<name>_<model>.hpp`).
  explicit SceneBuilder(std::string name);

  SceneBuilder& coordinates(std::vector<std::string> names);
  /// Parameters are kept in name order, as in a scene file (JetSpace::parameters()).
  SceneBuilder& parameter(const std::string& name, double value);
  /// Expressions in scene syntax: `m/2*x'^2`, derivatives with primes.
  SceneBuilder& lagrangian(std::string expression);
  /// One more constraint f^α = 0; multipliers lambda1… follow the order of the calls.
  SceneBuilder& constraint(std::string expression);
  /// Dependent coordinates d_1..d_g for the suslov model, one per constraint.
  SceneBuilder& dependent(std::vector<std::string> coordinates);
  /// Models to derive (default: all four).
  SceneBuilder& models(std::vector<ModelKind> models);
  /// [initial]: t0.
  SceneBuilder& initial_time(double t0);
  /// [initial]: value and derivatives of a coordinate or multiplier, [q, q', q'', …].
  SceneBuilder& initial(const std::string& variable, std::vector<double> values);
  /// [simulate]: the model to integrate and the solver settings.
  SceneBuilder& simulate(ModelKind model, double t_end, double rtol = 1e-8, double atol = 1e-10);
  /// [reference]: the exact q(t) of a coordinate.
  SceneBuilder& reference(const std::string& coordinate, std::string expression);
  /// [invariants]: a named quantity that should stay constant.
  SceneBuilder& invariant(const std::string& name, std::string expression);
  /// [definitions]: a named scalar, vector or matrix expression (`"[x, y, r]"`, `"rotz(psi)"`).
  SceneBuilder& definition(const std::string& name, std::string expression);
  /// [forces]: the generalized force Q_i(t, q, q') on a coordinate (docs/forces.md).
  SceneBuilder& force(const std::string& coordinate, std::string expression);

  /// The equivalent scene file; `nhc derive`/`generate`/`simulate` read it as it is.
  std::string toml() const;
  /// The validated scene. Throws InputError (see above).
  Scene build() const;

 private:
  struct SimulateEntry {
    ModelKind model;
    double t_end, rtol, atol;
  };
  std::string name_;
  std::vector<std::string> coordinates_;
  std::vector<std::pair<std::string, double>> parameters_;
  std::string lagrangian_;
  std::vector<std::string> constraints_;
  std::vector<std::string> dependent_;
  std::vector<ModelKind> models_;
  std::optional<double> t0_;
  std::vector<std::pair<std::string, std::vector<double>>> initial_;
  std::optional<SimulateEntry> simulate_;
  std::vector<std::pair<std::string, std::string>> reference_;
  std::vector<std::pair<std::string, std::string>> invariants_;
  std::vector<std::pair<std::string, std::string>> definitions_;
  std::vector<std::pair<std::string, std::string>> forces_;
};

}  // namespace nhc
