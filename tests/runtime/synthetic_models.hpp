#pragma once
// Two-state index-1 models built directly as tables, to drive the runtime's diagnostics:
// y0' = 1 (so y0 = t) and one algebraic equation for y1 that breaks down at t = 0.5.
#include <cmath>
#include <limits>

#include "nhc/runtime/model_table.h"

namespace synthetic {

inline constexpr const char* state_names[2] = {"u", "w"};
inline constexpr int state_variable[2] = {0, 1};
inline constexpr int state_order[2] = {0, 0};
inline constexpr double differential_id[2] = {1.0, 0.0};
inline constexpr const char* residual_names[2] = {"clock", "breakdown"};

/// F1 = w − 1 for u < 0.5, NaN after: a residual that is not finite past t = 0.5.
inline void nan_residual(double, const double* y, const double* yp, const double*, double* r) noexcept {
  r[0] = yp[0] - 1.0;
  r[1] = y[0] < 0.5 ? y[1] - 1.0 : std::numeric_limits<double>::quiet_NaN();
}
inline void nan_jacobian(double, const double* y, const double*, double cj, const double*, double* J) noexcept {
  J[0] = cj, J[1] = 0.0, J[2] = 0.0, J[3] = y[0] < 0.5 ? 1.0 : std::numeric_limits<double>::quiet_NaN();
}

/// F1 = max(0, 0.5 − u)(w − 1): dF1/dw vanishes from t = 0.5 on, the iteration matrix is singular.
inline void singular_residual(double, const double* y, const double* yp, const double*, double* r) noexcept {
  r[0] = yp[0] - 1.0;
  r[1] = std::max(0.0, 0.5 - y[0]) * (y[1] - 1.0);
}
inline void singular_jacobian(double, const double* y, const double*, double cj, const double*, double* J) noexcept {
  J[0] = cj;
  J[1] = y[0] < 0.5 ? -(y[1] - 1.0) : 0.0;
  J[2] = 0.0;
  J[3] = std::max(0.0, 0.5 - y[0]);
}

inline nhc_model_table table(void (*res)(double, const double*, const double*, const double*, double*),
                             void (*jac)(double, const double*, const double*, double, const double*, double*)) {
  nhc_model_table t{};
  t.abi_version = 2;
  t.scene_name = "synthetic";
  t.model_name = "test";
  t.n_states = 2;
  t.n_coordinates = 1;
  t.n_multipliers = 1;
  t.state_names = state_names;
  t.state_variable = state_variable;
  t.state_order = state_order;
  t.differential_id = differential_id;
  t.residual = res;
  t.jacobian = jac;
  t.residual_names = residual_names;
  return t;
}

}  // namespace synthetic

namespace synthetic::pendulum {
// The planar pendulum, x'' = −λ x, y'' = −λ y − g, x² + y² = 1, in the index-1 form Pryce's method
// gives (the constraint differentiated twice): the classic case where the hidden constraints
// g1 = x² + y² − 1 and g2 = x x' + y y' drift. States (x, x', y, y', lambda1); no Jacobian, so the
// runtime's difference-quotient path is used.
inline constexpr const char* state_names[5] = {"x", "x'", "y", "y'", "lambda1"};
inline constexpr int state_variable[5] = {0, 0, 1, 1, 2};
inline constexpr int state_order[5] = {0, 1, 0, 1, 0};
inline constexpr double differential_id[5] = {1, 1, 1, 1, 0};
inline constexpr const char* parameter_names[1] = {"g"};
inline constexpr double default_parameters[1] = {9.81};
inline constexpr const char* hidden_names[2] = {"f1", "D f1"};
inline constexpr const char* invariant_names[1] = {"energy"};

inline void residual(double, const double* y, const double* yp, const double* p, double* r) noexcept {
  r[0] = -yp[1] - y[4] * y[0];
  r[1] = -yp[3] - y[4] * y[2] - p[0];
  r[2] = y[0] * yp[1] + y[1] * y[1] + y[2] * yp[3] + y[3] * y[3];
  r[3] = yp[0] - y[1];
  r[4] = yp[2] - y[3];
}
inline void hidden(double, const double* y, const double*, double* g) noexcept {
  g[0] = y[0] * y[0] + y[2] * y[2] - 1.0;
  g[1] = y[0] * y[1] + y[2] * y[3];
}
inline void hidden_jacobian(double, const double* y, const double*, double* G) noexcept {
  const double rows[2][5] = {{2 * y[0], 0, 2 * y[2], 0, 0}, {y[1], y[0], y[3], y[2], 0}};
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 2; ++i) G[i + 2 * j] = rows[i][j];
}
inline void invariants(double, const double* y, const double*, const double* p, double* out) noexcept {
  out[0] = (y[1] * y[1] + y[3] * y[3]) / 2 + p[0] * y[2];
}

inline nhc_model_table table() {
  nhc_model_table t{};
  t.abi_version = 2;
  t.scene_name = "pendulum";
  t.model_name = "index1";
  t.n_states = 5;
  t.n_parameters = 1;
  t.n_coordinates = 2;
  t.n_multipliers = 1;
  t.n_hidden = 2;
  t.n_invariants = 1;
  t.state_names = state_names;
  t.state_variable = state_variable;
  t.state_order = state_order;
  t.differential_id = differential_id;
  t.parameter_names = parameter_names;
  t.default_parameters = default_parameters;
  t.hidden_names = hidden_names;
  t.invariant_names = invariant_names;
  t.residual = &residual;
  t.hidden_constraints = &hidden;
  t.hidden_constraints_jacobian = &hidden_jacobian;
  t.invariants = &invariants;
  return t;
}

}  // namespace synthetic::pendulum
