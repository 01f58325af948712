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
///
/// Such a matrix also keeps its factors (axis, angle) in order, so that omega() recognises Euler
/// angles: three elementary rotations R = R_a(q1) R_b(q2) R_c(q3) about coordinates, a ≠ b ≠ c. With
/// ω = q1' e_a + q2' R_a e_b + q3' R_a R_b e_c, det ∂ω/∂(q1', q2', q3') = det[e_a, e_b, R_b(q2) e_c],
/// which is ± sin q2 for proper Euler angles (c = a: z-x-z) and ± cos q2 for Tait–Bryan angles
/// (a, b, c distinct: z-y-x): where it vanishes ω no longer determines the rates (docs/quaternions.md).

#include <ginac/ginac.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nhc {

class JetSpace;

/// Euler angles that omega() or omega_body() met: a chain of three elementary rotations about
/// coordinates (value.hpp's header comment). The angular velocity stops determining the angle
/// rates where `determinant` (sin or cos of the middle angle) vanishes.
struct EulerChain {
  std::string axes;                 ///< "z-x-z"
  std::vector<std::string> angles;  ///< the three coordinates, in the chain's order
  GiNaC::ex determinant;            ///< sin(q2) (proper Euler angles) or cos(q2) (Tait–Bryan), in jet symbols
  std::string zeros;                ///< where the middle angle makes it vanish: "0, pi" or "-pi/2, pi/2"
  bool operator==(const EulerChain& o) const {
    return axes == o.axes && angles == o.angles && zeros == o.zeros && determinant.is_equal(o.determinant);
  }
};

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
  /// The elementary rotations (axis 0 x, 1 y, 2 z; angle) whose product the value is, in order;
  /// empty unless it is one (a transpose reverses them and negates the angles).
  std::vector<std::pair<int, GiNaC::ex>> factors;

  static Value scalar(const GiNaC::ex& e) { return {1, 1, {e}, std::nullopt, std::nullopt, {}}; }
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
  /// Where omega() and omega_body() add the Euler angles they meet (each chain once); null: nowhere.
  std::vector<EulerChain>* euler_chains = nullptr;
};
/// ValueError in words unless r is a 3×3 rotation: R Rᵀ = I symbolically where the expansion
/// shows it, else at check.point. `what` names the user of r in the message ("omega").
void require_rotation(const Value& r, const RotationCheck& check, const char* what);

/// Spatial angular velocity ω, Ṙ Rᵀ = [ω]×; body angular velocity Rᵀ ω, Rᵀ Ṙ = [Ω]×.
Value spatial_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check);
Value body_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check);

}  // namespace nhc
