// Hand-written to the contract of docs/generated-code.md (what `nhc generate` emits) for
// examples/appell_hamel.toml under Chetaev's model; the runtime's reference model and the
// hand-written limit of the benchmarks. Do not let it drift from the contract.
//
// Unknowns x, y, z, lambda1 (models.md, Appell–Hamel; k = b/a, v = sqrt(x'^2 + y'^2)):
//   R_x = -m x'' - lambda k x'/v,   R_y = -m y'' - lambda k y'/v,   R_z = -m g - m z'' + lambda,
//   f   = z' - k v.
// Pryce offsets: d = (2, 2, 2, 0), c = (0, 0, 0, 1): f is differentiated once,
//   D f = z'' - k (x' x'' + y' y'')/v,
// and f itself is the hidden constraint. States y = (x, x', y, y', z, z', lambda1).
#pragma once

#include <cmath>

#include "nhc/runtime/model_table.h"

namespace nhc_gen::appell_hamel_chetaev {

inline constexpr int n_states = 7;
inline constexpr int n_parameters = 4;
inline constexpr int n_coordinates = 3;
inline constexpr int n_multipliers = 1;
inline constexpr int n_hidden = 1;
inline constexpr int n_invariants = 1;
inline constexpr const char* model_name = "chetaev";
inline constexpr const char* scene_name = "appell_hamel";
inline constexpr const char* state_names[n_states] = {"x", "x'", "y", "y'", "z", "z'", "lambda1"};
inline constexpr int state_variable[n_states] = {0, 0, 1, 1, 2, 2, 3};
inline constexpr int state_order[n_states] = {0, 1, 0, 1, 0, 1, 0};
inline constexpr double differential_id[n_states] = {1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0};
inline constexpr const char* parameter_names[n_parameters] = {"m", "g", "a", "b"};
inline constexpr double default_parameters[n_parameters] = {1.0, 9.81, 1.0, 0.5};
inline constexpr const char* hidden_names[n_hidden] = {"f1"};
inline constexpr const char* invariant_names[n_invariants] = {"energy"};

// F(t, y, y') = 0: R_x, R_y, R_z, D f1, then the chain rows of x, y, z.
inline void residual(double t, const double* y, const double* yp, const double* p, double* r) noexcept {
  (void)t;
  const double m = p[0], g = p[1], k = p[3] / p[2];
  const double v = std::sqrt(y[1] * y[1] + y[3] * y[3]);
  const double lam = y[6];
  r[0] = -m * yp[1] - lam * k * y[1] / v;
  r[1] = -m * yp[3] - lam * k * y[3] / v;
  r[2] = -m * g - m * yp[5] + lam;
  r[3] = yp[5] - k * (y[1] * yp[1] + y[3] * yp[3]) / v;
  r[4] = yp[0] - y[1];
  r[5] = yp[2] - y[3];
  r[6] = yp[4] - y[5];
}

// J = dF/dy + cj dF/dy', column-major 7 x 7.
inline void jacobian(double t, const double* y, const double* yp, double cj, const double* p, double* J) noexcept {
  (void)t;
  for (int i = 0; i < n_states * n_states; ++i) J[i] = 0.0;
  const double m = p[0], k = p[3] / p[2];
  const double x1 = y[1], y1 = y[3], lam = y[6];
  const double v = std::sqrt(x1 * x1 + y1 * y1);
  const double v3 = v * v * v;
  const double w = x1 * yp[1] + y1 * yp[3];
  auto at = [J](int row, int col) -> double& { return J[row + n_states * col]; };
  // R_x
  at(0, 1) = -lam * k * y1 * y1 / v3 - m * cj;
  at(0, 3) = lam * k * x1 * y1 / v3;
  at(0, 6) = -k * x1 / v;
  // R_y
  at(1, 1) = lam * k * x1 * y1 / v3;
  at(1, 3) = -lam * k * x1 * x1 / v3 - m * cj;
  at(1, 6) = -k * y1 / v;
  // R_z
  at(2, 5) = -m * cj;
  at(2, 6) = 1.0;
  // D f1
  at(3, 1) = -k * (yp[1] / v - w * x1 / v3) - cj * k * x1 / v;
  at(3, 3) = -k * (yp[3] / v - w * y1 / v3) - cj * k * y1 / v;
  at(3, 5) = cj;
  // chain rows
  at(4, 0) = cj;
  at(4, 1) = -1.0;
  at(5, 2) = cj;
  at(5, 3) = -1.0;
  at(6, 4) = cj;
  at(6, 5) = -1.0;
}

inline constexpr int jacobian_nnz = 17;
inline constexpr int jacobian_colptr[n_states + 1] = {0, 1, 5, 6, 10, 11, 14, 17};
inline constexpr int jacobian_rowind[jacobian_nnz] = {4, 0, 1, 3, 4, 5, 0, 1, 3, 5, 6, 2, 3, 6, 0, 1, 2};

inline void jacobian_values(double t, const double* y, const double* yp, double cj, const double* p,
                            double* values) noexcept {
  double J[n_states * n_states];
  jacobian(t, y, yp, cj, p, J);
  for (int col = 0; col < n_states; ++col)
    for (int e = jacobian_colptr[col]; e < jacobian_colptr[col + 1]; ++e)
      values[e] = J[jacobian_rowind[e] + n_states * col];
}

// Hidden constraint f1 = z' - k v and its gradient G = df1/dy (1 x 7).
inline void hidden_constraints(double t, const double* y, const double* p, double* g) noexcept {
  (void)t;
  const double k = p[3] / p[2];
  g[0] = y[5] - k * std::sqrt(y[1] * y[1] + y[3] * y[3]);
}

inline void hidden_constraints_jacobian(double t, const double* y, const double* p, double* G) noexcept {
  (void)t;
  const double k = p[3] / p[2];
  const double v = std::sqrt(y[1] * y[1] + y[3] * y[3]);
  for (int i = 0; i < n_states; ++i) G[i] = 0.0;
  G[1] = -k * y[1] / v;
  G[3] = -k * y[3] / v;
  G[5] = 1.0;
}

inline void invariants(double t, const double* y, const double* yp, const double* p, double* out) noexcept {
  (void)t;
  (void)yp;
  const double m = p[0], g = p[1];
  out[0] = m / 2 * (y[1] * y[1] + y[3] * y[3] + y[5] * y[5]) + m * g * y[4];
}

// ---- Runtime additions (docs/generated-code.md) ----
inline constexpr const char* residual_names[n_states] = {"R_x",           "R_y",           "R_z",          "D f1",
                                                         "chain x' = x'", "chain y' = y'", "chain z' = z'"};
inline constexpr int n_singular = 1;
inline constexpr const char* singular_names[n_singular] = {"x'^2 + y'^2 (under the square root in df1/dx', df1/dy')"};
inline void singular_quantities(double t, const double* y, const double* p, double* s) noexcept {
  (void)t;
  (void)p;
  s[0] = y[1] * y[1] + y[3] * y[3];
}

/// The C table (nhc/runtime/model_table.h), filled by field name; the rest stays zero.
inline nhc_model_table make_model_table() noexcept {
  nhc_model_table t{};
  t.abi_version = 2;
  t.scene_name = scene_name;
  t.model_name = model_name;
  t.n_states = n_states;
  t.n_parameters = n_parameters;
  t.n_coordinates = n_coordinates;
  t.n_multipliers = n_multipliers;
  t.n_hidden = n_hidden;
  t.n_invariants = n_invariants;
  t.state_names = state_names;
  t.state_variable = state_variable;
  t.state_order = state_order;
  t.differential_id = differential_id;
  t.parameter_names = parameter_names;
  t.default_parameters = default_parameters;
  t.hidden_names = hidden_names;
  t.invariant_names = invariant_names;
  t.residual = &residual;
  t.jacobian = &jacobian;
  t.jacobian_nnz = jacobian_nnz;
  t.jacobian_colptr = jacobian_colptr;
  t.jacobian_rowind = jacobian_rowind;
  t.jacobian_values = &jacobian_values;
  t.hidden_constraints = &hidden_constraints;
  t.hidden_constraints_jacobian = &hidden_constraints_jacobian;
  t.invariants = &invariants;
  t.residual_names = residual_names;
  t.n_singular = n_singular;
  t.singular_names = singular_names;
  t.singular_quantities = &singular_quantities;
  return t;
}

inline const nhc_model_table* model_table() noexcept {
  static const nhc_model_table table = make_model_table();
  return &table;
}

}  // namespace nhc_gen::appell_hamel_chetaev

#ifdef NHC_EXPORT_MODEL_TABLE
extern "C" const nhc_model_table* nhc_model_table_get(void) { return nhc_gen::appell_hamel_chetaev::model_table(); }
#endif
