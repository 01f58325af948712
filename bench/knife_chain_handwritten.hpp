// Hand-written to the contract of docs/generated-code.md for the benchmark family of
// bench/knife_chain.py under Chetaev's model: the hand-written limit the generated code of
// `nhc generate bench-scenes/knife_chain_<N>.toml` is measured against (bench/run.sh).
//
// Define NHC_BENCH_CHAIN_N (>= 1) before including. The layout equals the generated one, so both
// integrate the same index-1 system with the same states:
//   coordinates c = 3(i-1) + {0, 1, 2} = x_i, y_i, th_i (i = 1..N); states y[2c] = q_c,
//   y[2c+1] = q_c', then y[6N + i-1] = lambda_i (algebraic);
//   rows 0..3N-1: R_c = E_c(L) + lambda_i df_i/dq_c'; rows 3N + i-1: D f_i; rows 4N + c: the
//   chain rows yp[2c] - y[2c+1].
// With f_i = x_i' sin th_i - y_i' cos th_i and the Lagrangian of bench/knife_chain.py:
//   R_x_i  = lambda_i sin th_i + m g sin(alpha) - m x_i'' - k (2 x_i - x_{i-1} - x_{i+1})
//   R_y_i  = -lambda_i cos th_i - m y_i'' - k (y_i - y_{i-1} - l) + k (y_{i+1} - y_i - l)
//   R_th_i = -J th_i''
//   D f_i  = x_i'' s + x_i' th_i' c - y_i'' c + y_i' th_i' s      (s = sin th_i, c = cos th_i)
// (the spring terms with i-1 or i+1 only where that neighbour exists).
// Parameters in this header's own order (m, J, g, alpha, k, l), defaults = bench/knife_chain.py.
#pragma once

#include <cmath>
#include <cstdio>

#ifndef NHC_BENCH_CHAIN_N
#error "define NHC_BENCH_CHAIN_N (the number of knife edges) before including knife_chain_handwritten.hpp"
#endif

#include "nhc/runtime/model_table.h"

namespace nhc_gen::knife_chain_chetaev {

inline constexpr int N = NHC_BENCH_CHAIN_N;
static_assert(N >= 1, "NHC_BENCH_CHAIN_N must be at least 1");

inline constexpr int n_states = 7 * N;
inline constexpr int n_parameters = 6;
inline constexpr int n_coordinates = 3 * N;
inline constexpr int n_multipliers = N;
inline constexpr int n_hidden = N;
inline constexpr int n_invariants = 0;
inline constexpr int n_reference = 0;
inline constexpr int n_singular = 0;
inline constexpr const char* model_name = "chetaev";
inline constexpr const char* scene_name = "knife_chain";
inline constexpr const char* parameter_names[n_parameters] = {"m", "J", "g", "alpha", "k", "l"};
inline constexpr double default_parameters[n_parameters] = {1.0, 0.1, 9.81, 0.3, 10.0, 1.0};

/// Number of Jacobian nonzeros: per knife edge, columns x and y hold their own R row, one per
/// neighbour and the chain row; th: R_x, R_y, D f, chain; x', y', th': three each; lambda: two.
inline constexpr int jacobian_nnz = N == 1 ? 17 : 2 * (4 * N - 2) + 15 * N;

/// Metadata arrays, built at compile time.
struct Tables {
  int state_variable[n_states] = {};
  int state_order[n_states] = {};
  double differential_id[n_states] = {};
  int colptr[n_states + 1] = {};
  int rowind[jacobian_nnz] = {};
};

constexpr Tables make_tables() {
  Tables t{};
  for (int c = 0; c < 3 * N; ++c) {
    t.state_variable[2 * c] = c;
    t.state_variable[2 * c + 1] = c;
    t.state_order[2 * c] = 0;
    t.state_order[2 * c + 1] = 1;
    t.differential_id[2 * c] = 1.0;
    t.differential_id[2 * c + 1] = 1.0;
  }
  for (int a = 0; a < N; ++a) {
    t.state_variable[6 * N + a] = 3 * N + a;
    t.state_order[6 * N + a] = 0;
    t.differential_id[6 * N + a] = 0.0;
  }
  int e = 0;
  int col = 0;
  for (int i = 0; i < N; ++i) {
    for (int q = 0; q < 3; ++q) {
      const int c = 3 * i + q;
      // position column
      t.colptr[col++] = e;
      if (q < 2) {
        if (i > 0) t.rowind[e++] = c - 3;
        if (N > 1) t.rowind[e++] = c;
        if (i + 1 < N) t.rowind[e++] = c + 3;
      } else {
        t.rowind[e++] = 3 * i;      // R_x_i
        t.rowind[e++] = 3 * i + 1;  // R_y_i
        t.rowind[e++] = 3 * N + i;  // D f_i
      }
      t.rowind[e++] = 4 * N + c;  // chain
      // velocity column
      t.colptr[col++] = e;
      t.rowind[e++] = c;
      t.rowind[e++] = 3 * N + i;
      t.rowind[e++] = 4 * N + c;
    }
  }
  for (int a = 0; a < N; ++a) {
    t.colptr[col++] = e;
    t.rowind[e++] = 3 * a;
    t.rowind[e++] = 3 * a + 1;
  }
  t.colptr[col] = e;
  return t;
}

inline constexpr Tables tables = make_tables();
static_assert(tables.colptr[n_states] == jacobian_nnz, "Jacobian structure and count disagree");

inline constexpr const int* state_variable = tables.state_variable;
inline constexpr const int* state_order = tables.state_order;
inline constexpr const double* differential_id = tables.differential_id;
inline constexpr const int* jacobian_colptr = tables.colptr;
inline constexpr const int* jacobian_rowind = tables.rowind;

/// Names ("x1", "x1'", …, "lambda1"); built once at first use.
struct Names {
  char storage[15 * N][48] = {};
  const char* state[n_states] = {};
  const char* hidden[n_hidden] = {};
  const char* residual[n_states] = {};
  Names() {
    static const char* const base[3] = {"x", "y", "th"};
    int s = 0;
    for (int i = 0; i < N; ++i)
      for (int q = 0; q < 3; ++q) {
        const int c = 3 * i + q;
        std::snprintf(storage[s], sizeof storage[s], "%s%d", base[q], i + 1);
        state[2 * c] = storage[s++];
        std::snprintf(storage[s], sizeof storage[s], "%s%d'", base[q], i + 1);
        state[2 * c + 1] = storage[s++];
        std::snprintf(storage[s], sizeof storage[s], "R_%s%d", base[q], i + 1);
        residual[c] = storage[s++];
        std::snprintf(storage[s], sizeof storage[s], "chain %s%d' = %s%d'", base[q], i + 1, base[q], i + 1);
        residual[4 * N + c] = storage[s++];
      }
    for (int a = 0; a < N; ++a) {
      std::snprintf(storage[s], sizeof storage[s], "lambda%d", a + 1);
      state[6 * N + a] = storage[s++];
      std::snprintf(storage[s], sizeof storage[s], "f%d", a + 1);
      hidden[a] = storage[s++];
      std::snprintf(storage[s], sizeof storage[s], "D f%d", a + 1);
      residual[3 * N + a] = storage[s++];
    }
  }
};
inline const Names& names() {
  static const Names n;
  return n;
}

// F(t, y, y') = 0.
inline void residual(double /*t*/, const double* y, const double* yp, const double* p, double* r) noexcept {
  const double m = p[0], J = p[1], k = p[4], l = p[5];
  const double gravity = m * p[2] * std::sin(p[3]);
  for (int i = 0; i < N; ++i) {
    const double* q = y + 6 * i;  // x, x', y, y', th, th'
    const double* qp = yp + 6 * i;
    const double lam = y[6 * N + i];
    const double s = std::sin(q[4]), c = std::cos(q[4]);
    double fx = gravity, fy = 0.0;
    if (i > 0) {
      fx -= k * (q[0] - q[-6]);
      fy -= k * (q[2] - q[-4] - l);
    }
    if (i + 1 < N) {
      fx += k * (q[6] - q[0]);
      fy += k * (q[8] - q[2] - l);
    }
    r[3 * i] = lam * s + fx - m * qp[1];
    r[3 * i + 1] = fy - lam * c - m * qp[3];
    r[3 * i + 2] = -J * qp[5];
    r[3 * N + i] = s * (qp[1] + q[3] * q[5]) + c * (q[1] * q[5] - qp[3]);
    for (int d = 0; d < 3; ++d) r[4 * N + 3 * i + d] = qp[2 * d] - q[2 * d + 1];
  }
}

// Nonzero values of J = dF/dy + cj dF/dy' in the order of jacobian_colptr / jacobian_rowind.
inline void jacobian_values(double /*t*/, const double* y, const double* yp, double cj, const double* p,
                            double* v) noexcept {
  const double m = p[0], J = p[1], k = p[4];
  const double mcj = -m * cj, Jcj = -J * cj;
  double sc[2 * N];  // sin, cos of each th_i, for the multiplier columns
  int e = 0;
  for (int i = 0; i < N; ++i) {
    const double* q = y + 6 * i;
    const double* qp = yp + 6 * i;
    const double lam = y[6 * N + i];
    const double s = std::sin(q[4]), c = std::cos(q[4]);
    sc[2 * i] = s, sc[2 * i + 1] = c;
    const double diag = -k * ((i > 0) + (i + 1 < N));
    for (int d = 0; d < 2; ++d) {  // x, then y: position and velocity columns
      if (i > 0) v[e++] = k;
      if (N > 1) v[e++] = diag;
      if (i + 1 < N) v[e++] = k;
      v[e++] = cj;
      v[e++] = mcj;
      v[e++] = d == 0 ? cj * s + c * q[5] : s * q[5] - cj * c;
      v[e++] = -1.0;
    }
    // th
    v[e++] = lam * c;
    v[e++] = lam * s;
    v[e++] = c * (qp[1] + q[3] * q[5]) - s * (q[1] * q[5] - qp[3]);
    v[e++] = cj;
    // th'
    v[e++] = Jcj;
    v[e++] = c * q[1] + s * q[3];
    v[e++] = -1.0;
  }
  for (int a = 0; a < N; ++a) {
    v[e++] = sc[2 * a];
    v[e++] = -sc[2 * a + 1];
  }
}

// Dense J, column-major n_states x n_states.
inline void jacobian(double /*t*/, const double* y, const double* yp, double cj, const double* p, double* Jd) noexcept {
  for (int e = 0; e < n_states * n_states; ++e) Jd[e] = 0.0;
  auto at = [Jd](int row, int col) -> double& { return Jd[row + n_states * col]; };
  const double m = p[0], J = p[1], k = p[4];
  const double mcj = -m * cj, Jcj = -J * cj;
  for (int i = 0; i < N; ++i) {
    const double* q = y + 6 * i;
    const double* qp = yp + 6 * i;
    const double lam = y[6 * N + i];
    const double s = std::sin(q[4]), c = std::cos(q[4]);
    const int rx = 3 * i, ry = 3 * i + 1, rth = 3 * i + 2, rf = 3 * N + i, chain = 4 * N + 3 * i;
    const int cx = 6 * i, cy = 6 * i + 2, cth = 6 * i + 4;
    // springs
    if (i > 0) {
      at(rx, cx) -= k, at(rx - 3, cx) = k;
      at(ry, cy) -= k, at(ry - 3, cy) = k;
    }
    if (i + 1 < N) {
      at(rx, cx) -= k, at(rx + 3, cx) = k;
      at(ry, cy) -= k, at(ry + 3, cy) = k;
    }
    // chain rows
    for (int d = 0; d < 3; ++d) {
      at(chain + d, cx + 2 * d) = cj;
      at(chain + d, cx + 2 * d + 1) = -1.0;
    }
    at(rx, cx + 1) = mcj;
    at(ry, cy + 1) = mcj;
    at(rth, cth + 1) = Jcj;
    at(rf, cx + 1) = cj * s + c * q[5];
    at(rf, cy + 1) = s * q[5] - cj * c;
    at(rx, cth) = lam * c;
    at(ry, cth) = lam * s;
    at(rf, cth) = c * (qp[1] + q[3] * q[5]) - s * (q[1] * q[5] - qp[3]);
    at(rf, cth + 1) = c * q[1] + s * q[3];
    at(rx, 6 * N + i) = s;
    at(ry, 6 * N + i) = -c;
  }
}

// Hidden constraints f_i and G = df/dy (column-major n_hidden x n_states).
inline void hidden_constraints(double /*t*/, const double* y, const double* /*p*/, double* g) noexcept {
  for (int i = 0; i < N; ++i) {
    const double* q = y + 6 * i;
    g[i] = q[1] * std::sin(q[4]) - q[3] * std::cos(q[4]);
  }
}

inline void hidden_constraints_jacobian(double /*t*/, const double* y, const double* /*p*/, double* G) noexcept {
  for (int i = 0; i < n_hidden * n_states; ++i) G[i] = 0.0;
  for (int i = 0; i < N; ++i) {
    const double* q = y + 6 * i;
    const double s = std::sin(q[4]), c = std::cos(q[4]);
    G[i + n_hidden * (6 * i + 1)] = s;
    G[i + n_hidden * (6 * i + 3)] = -c;
    G[i + n_hidden * (6 * i + 4)] = q[1] * c + q[3] * s;
  }
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
  t.n_reference = n_reference;
  t.state_names = names().state;
  t.state_variable = state_variable;
  t.state_order = state_order;
  t.differential_id = differential_id;
  t.parameter_names = parameter_names;
  t.default_parameters = default_parameters;
  t.hidden_names = names().hidden;
  t.residual = &residual;
  t.jacobian = &jacobian;
  t.jacobian_nnz = jacobian_nnz;
  t.jacobian_colptr = jacobian_colptr;
  t.jacobian_rowind = jacobian_rowind;
  t.jacobian_values = &jacobian_values;
  t.hidden_constraints = &hidden_constraints;
  t.hidden_constraints_jacobian = &hidden_constraints_jacobian;
  t.residual_names = names().residual;
  t.n_singular = n_singular;
  return t;
}

inline const nhc_model_table* model_table() noexcept {
  static const nhc_model_table table = make_model_table();
  return &table;
}

}  // namespace nhc_gen::knife_chain_chetaev

#ifdef NHC_EXPORT_MODEL_TABLE
extern "C" const nhc_model_table* nhc_model_table_get(void) { return nhc_gen::knife_chain_chetaev::model_table(); }
#endif
