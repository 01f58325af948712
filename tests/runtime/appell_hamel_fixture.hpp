#pragma once
// Appell–Hamel under Chetaev's model (models.md): closed form and initial data shared by the
// [runtime] tests. k = b/a, v = sqrt(x'^2 + y'^2):
//   the horizontal direction u = (x', y')/v is constant, v' = −g k/(1 + k^2), z' = k v,
//   lambda = m g/(1 + k^2), and v reaches 0 at t* = v0 (a^2 + b^2)/(g a b).
#include <cmath>
#include <vector>

#include "handwritten/appell_hamel_chetaev.hpp"
#include "nhc/runtime/runtime.hpp"

namespace ah_test {

struct AppellHamel {
  double m = 1.0, g = 9.81, a = 1.0, b = 0.5;
  double x0 = 0, y0 = 0, z0 = 0, vx0 = 1.0, vy0 = 0.5;

  double k() const { return b / a; }
  double v0() const { return std::hypot(vx0, vy0); }
  double deceleration() const { return g * k() / (1 + k() * k()); }
  double t_star() const { return v0() * (a * a + b * b) / (g * a * b); }
  std::vector<double> parameters() const { return {m, g, a, b}; }

  /// Exact states (x, x', y, y', z, z', lambda1) at t < t*.
  std::vector<double> exact(double t) const {
    const double ux = vx0 / v0(), uy = vy0 / v0();
    const double s = v0() * t - deceleration() * t * t / 2;  // horizontal arc length
    const double v = v0() - deceleration() * t;
    return {x0 + ux * s, ux * v, y0 + uy * s, uy * v, z0 + k() * s, k() * v, m * g / (1 + k() * k())};
  }

  /// The scene's [initial]: x, x', y, y', z given; z' and lambda1 left to the runtime.
  nhc::runtime::InitialState initial() const {
    nhc::runtime::InitialState s;
    s.t0 = 0;
    s.y = {x0, vx0, y0, vy0, z0, 0.0, 0.0};
    s.given = {true, true, true, true, true, false, false};
    return s;
  }
};

inline nhc::runtime::Model model() { return NHC_RUNTIME_MODEL(nhc_gen::appell_hamel_chetaev); }

}  // namespace ah_test
