#pragma once
/// \file value.hpp
/// \brief Values of the scene language: scalars, vectors (n×1) and matrices (n×m) of GiNaC
/// expressions, and the linear algebra a scene may write on them (README.md, "Definitions").
///
/// A 1×1 result is a scalar. Every operation checks shapes and throws ValueError with a message
/// in words; the expression parser turns it into a positioned error.
///
/// A 3×3 matrix built from rotx/roty/rotz by products and transposes also carries its spatial
/// angular velocity ω, where Ṙ Rᵀ = [ω]× (the skew matrix of ω), composed in closed form:
///   ω(rotx(θ)) = θ' e_x,   ω(R₁R₂) = ω(R₁) + R₁ ω(R₂),   ω(Rᵀ) = −Ω(R),
/// and its body angular velocity Ω, Rᵀ Ṙ = [Ω]×:
///   Ω(rotx(θ)) = θ' e_x,   Ω(R₁R₂) = R₂ᵀ Ω(R₁) + Ω(R₂),   Ω(Rᵀ) = −ω(R).
/// omega(R) and omega_body(R) then return them without differentiating R entry by entry: the result has no
/// sin² + cos² left for the derivation to carry (Goldstein, Classical Mechanics, §4.8).

#include <ginac/ginac.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace nhc {

class JetSpace;

/// A shape or domain error of the scene language ("dot of a 3-vector and a 2-vector").
class ValueError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Value {
  unsigned rows = 1;
  unsigned cols = 1;
  std::vector<GiNaC::ex> entries;  ///< row-major, rows × cols
  /// Spatial angular velocity (3 entries) when the value is a rotation composed of rotx/roty/rotz.
  std::optional<std::vector<GiNaC::ex>> angular_velocity;
  std::optional<std::vector<GiNaC::ex>> body_angular_velocity;  ///< Ω, with angular_velocity

  static Value scalar(const GiNaC::ex& e) { return {1, 1, {e}, std::nullopt, std::nullopt}; }
  static Value vector(std::vector<GiNaC::ex> entries);
  static Value matrix(unsigned rows, unsigned cols, std::vector<GiNaC::ex> entries);

  bool is_scalar() const { return rows == 1 && cols == 1; }
  bool is_vector() const { return cols == 1 && rows > 1; }
  bool is_square3() const { return rows == 3 && cols == 3; }
  const GiNaC::ex& at(unsigned i, unsigned j) const { return entries[i * cols + j]; }
  /// "a scalar", "a 3-vector", "a 3x3 matrix".
  std::string describe() const;
};

Value operator-(const Value& a);
Value add(const Value& a, const Value& b);       ///< same shapes
Value subtract(const Value& a, const Value& b);  ///< same shapes
/// scalar·any, any·scalar, matrix·vector, matrix·matrix (inner sizes equal).
Value multiply(const Value& a, const Value& b);
Value transpose(const Value& a);
/// 1-based components: v[i] of a vector, M[i, j] of a matrix.
Value component(const Value& a, const std::vector<long>& indices);
GiNaC::ex dot(const Value& a, const Value& b);  ///< vectors of one length
Value cross(const Value& a, const Value& b);    ///< 3-vectors
GiNaC::ex norm(const Value& a);                 ///< sqrt(dot(a, a))

/// Entry-wise total derivative D^k on the jet (models.md, "Notation").
Value total_derivative(const Value& a, const JetSpace& jet, int k);

/// Elementary rotations about the x, y, z axes by `angle` (right-handed, active).
Value rotation_x(const GiNaC::ex& angle, const JetSpace& jet);
Value rotation_y(const GiNaC::ex& angle, const JetSpace& jet);
Value rotation_z(const GiNaC::ex& angle, const JetSpace& jet);

/// The rotation of the unit quaternion q = (q0, q1, q2, q3), scalar first (Shuster 1993, eq. 161):
///   R = (q0² − v·v) I + 2 v vᵀ + 2 q0 [v]×,   v = (q1, q2, q3),
/// with ω = 2 (q0 v' − q0' v + v × v') and Ω = 2 (q0 v' − q0' v − v × v') (from q' = ½ (0, ω) ⊗ q
/// = ½ q ⊗ (0, Ω)). Both hold where |q| = 1, which the scene keeps as a holonomic constraint
/// (docs/quaternions.md); R, ω and Ω are polynomials in q and q', singular nowhere.
Value rotation_of_quaternion(const std::vector<GiNaC::ex>& q, const JetSpace& jet);

/// How omega() decides that its argument is a rotation when ω is not known in closed form:
/// symbolically (R Rᵀ − I expands to zero), else numerically at `point` (parameters and initial
/// values; symbols it does not cover take fixed values in [0.25, 1.25)).
struct RotationCheck {
  const GiNaC::exmap* point = nullptr;
};
/// ValueError in words unless r is a 3×3 rotation: R Rᵀ = I symbolically where the expansion
/// shows it, else at check.point. `what` names the user of r in the message ("omega").
void require_rotation(const Value& r, const RotationCheck& check, const char* what);

/// Spatial angular velocity ω, Ṙ Rᵀ = [ω]×; body angular velocity Rᵀ ω, Rᵀ Ṙ = [Ω]×.
Value spatial_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check);
Value body_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check);

}  // namespace nhc
