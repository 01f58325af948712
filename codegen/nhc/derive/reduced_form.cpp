#include "nhc/derive/reduced_form.hpp"
#include "nhc/expr/stable_symbol.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <set>

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/symbol_substitution.hpp"
#include "nhc/expr/work_budget.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/base/primed_name.hpp"

namespace nhc {

namespace {

using GiNaC::ex;

/// The constraint Jacobian's columns are taken as independent when the smallest pivot of the
/// column-pivoted QR is above this fraction of the largest (docs/reduced-form.md, "Speeds").
constexpr double kRankTolerance = 1e-9;

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// e as an intermediate called `name` when it is not small (the one size policy of
/// intermediate.hpp), else e itself.
ex named(const ex& e, const std::string& name, const std::string& latex) {
  const ex s = simplified_where_it_pays(e);
  if (expression_nodes(s) < kInlineBelowNodes) return s;
  return Intermediate(name, latex, s);
}

/// The numeric rank of the columns `columns` of a.
int rank_of_columns(const Eigen::MatrixXd& a, const std::vector<int>& columns) {
  if (columns.empty()) return 0;
  Eigen::MatrixXd m(a.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) m.col(static_cast<Eigen::Index>(k)) = a.col(columns[k]);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(m);
  qr.setThreshold(kRankTolerance);
  return static_cast<int>(qr.rank());
}

/// Solves m X = rhs for X (m square, symbolic), each entry put over a common denominator
/// where small.
GiNaC::matrix solve(const GiNaC::matrix& m, const GiNaC::matrix& rhs) {
  GiNaC::matrix vars(m.cols(), rhs.cols());
  for (unsigned r = 0; r < vars.rows(); ++r)
    for (unsigned c = 0; c < vars.cols(); ++c)
      vars(r, c) = stable_symbol("solve_" + std::to_string(r) + "_" + std::to_string(c));  // see stable_symbol.hpp
  GiNaC::matrix x = m.solve(vars, rhs, GiNaC::solve_algo::gauss);
  for (unsigned r = 0; r < x.rows(); ++r)
    for (unsigned c = 0; c < x.cols(); ++c) x(r, c) = work_budget::normal(x(r, c));
  return x;
}

/// df/dq' (the velocity-level constraints' A) evaluated at the scene's initial point: t0, q from
/// [initial] (missing values 0), the parameters and the inputs at t0; nullopt where an entry has
/// no finite value there.
std::optional<Eigen::MatrixXd> jacobian_at_initial_point(const Scene& scene, const GiNaC::matrix& A) {
  const JetSpace& jet = *scene.jet;
  const auto& names = jet.coordinates();
  GiNaC::exmap point = scene.parameter_substitution();
  try {
    for (const auto& [symbol, value] : scene.input_substitution(scene.initial.t0)) point[symbol] = value;
  } catch (const MathError&) {
  }  // an input without a value there leaves A unevaluated below
  point[jet.time()] = scene.initial.t0;
  for (int j = 0; j < jet.coordinate_count(); ++j) {
    const auto it = scene.initial.values.find(names[static_cast<std::size_t>(j)]);
    point[jet.q(j, 0)] = it != scene.initial.values.end() && !it->second.empty() ? it->second.front() : 0.0;
  }
  Eigen::MatrixXd A0(A.rows(), A.cols());
  for (unsigned a = 0; a < A.rows(); ++a)
    for (unsigned j = 0; j < A.cols(); ++j) {
      const auto value = finite_value(substitute_symbols(A(a, j), point), {});
      if (!value) return std::nullopt;
      A0(a, j) = *value;
    }
  return A0;
}

/// The default rule's dependent coordinates (docs/reduced-form.md, "Which speeds are
/// independent"): the first g columns of A0, in the coordinates' order, that are independent;
/// fewer when A0 has rank below g.
std::vector<int> first_independent_columns(const Eigen::MatrixXd& A0, int g) {
  std::vector<int> columns;
  for (int j = 0; j < A0.cols() && static_cast<int>(columns.size()) < g; ++j) {
    columns.push_back(j);
    if (rank_of_columns(A0, columns) < static_cast<int>(columns.size())) columns.pop_back();
  }
  return columns;
}

}  // namespace

std::optional<std::vector<int>> default_dependent_coordinates(const Scene& scene) {
  const int g = scene.constraint_count();
  if (g > 0 && static_cast<int>(scene.dependent.size()) == g) {
    std::vector<int> out = scene.dependent;
    std::sort(out.begin(), out.end());
    return out;
  }
  const JetSpace& jet = *scene.jet;
  const int n = jet.coordinate_count();
  GiNaC::matrix A(static_cast<unsigned>(g), static_cast<unsigned>(n));
  for (int a = 0; a < g; ++a) {
    const ex& f = scene.constraints[static_cast<std::size_t>(a)];
    const int m = jet.highest_coordinate_order(f);
    if (m != 0 && m != 1) return std::nullopt;  // the reduced form refuses these
    const ex v = m == 0 ? jet.total_derivative(f) : f;
    for (int j = 0; j < n; ++j) {
      const ex aj = partial_derivative(v, GiNaC::ex_to<GiNaC::symbol>(jet.q(j, 1)));
      if (jet.highest_coordinate_order(aj) > 0) return std::nullopt;
      A(static_cast<unsigned>(a), static_cast<unsigned>(j)) = aj;
    }
  }
  const std::optional<Eigen::MatrixXd> A0 = jacobian_at_initial_point(scene, A);
  if (!A0) return std::nullopt;
  std::vector<int> columns = first_independent_columns(*A0, g);
  if (static_cast<int>(columns.size()) < g) return std::nullopt;
  return columns;
}

std::vector<std::string> parse_speed_list(const std::string& text) {
  std::vector<std::string> out;
  std::string current;
  auto flush = [&] {
    const auto b = current.find_first_not_of(" \t");
    const auto e = current.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? "" : current.substr(b, e - b + 1));
    current.clear();
  };
  for (char ch : text) {
    if (ch == ',') flush();
    else current += ch;
  }
  flush();
  return out;
}

std::vector<GiNaC::ex> ReducedForm::expressions() const {
  std::vector<ex> out = dependent_speeds;
  for (unsigned r = 0; r < mass_matrix.rows(); ++r)
    for (unsigned c = 0; c < mass_matrix.cols(); ++c) out.push_back(mass_matrix(r, c));
  out.insert(out.end(), forcing.begin(), forcing.end());
  out.insert(out.end(), multipliers.begin(), multipliers.end());
  return out;
}

ReducedForm reduce_to_independent_speeds(const Scene& scene, const DerivedModel& model,
                                         const std::vector<std::string>& speeds, const std::string& flag) {
  const work_budget::Stage stage("reducing to independent speeds");
  const JetSpace& jet = *scene.jet;
  const int n = jet.coordinate_count();
  const int g = scene.constraint_count();
  const auto& names = jet.coordinates();
  ReducedForm out;
  auto refuse = [&](const std::string& reason) {
    out.available = false;
    out.reason = reason;
    return out;
  };
  if (!model.applicable) return refuse("the model does not apply: " + model.reason);
  if (model.kind != ModelKind::chetaev && model.kind != ModelKind::holder)
    return refuse(
        "the multiplier-free form is that of the chetaev and holder models (constraint forces "
        "lambda*df/dq'); the " +
        to_string(model.kind) + " model's equations are not of that form");

  // The constraints at velocity level, A q' + b = 0.
  std::vector<ex> velocity(static_cast<std::size_t>(g));
  for (int a = 0; a < g; ++a) {
    const ex& f = scene.constraints[static_cast<std::size_t>(a)];
    const int m = jet.highest_coordinate_order(f);
    const std::string fa = "f" + std::to_string(a + 1);
    if (model.kind == ModelKind::holder && m != 1)
      return refuse("constraint " + fa + " is of order " + std::to_string(m) +
                    "; the holder model's multiplier-free form takes constraints on velocities only");
    // docs/reduced-form.md, "Constraints of higher order": why these are refused.
    if (m == 2)
      return refuse("constraint " + fa +
                    " is of order 2: it leaves every speed a state, so its multiplier-free "
                    "form would be on independent accelerations, not speeds, which nhc does not build (the "
                    "multiplier-free form takes constraints on positions and velocities)");
    if (m > 2)
      return refuse("constraint " + fa + " is of order " + std::to_string(m) +
                    ": its multiplier is fixed only by the "
                    "derivatives of the second-order equations, so the accelerations are part of the state "
                    "and the equations are not of the form M_r u' = f_r on speeds (the multiplier-free form "
                    "takes constraints on positions and velocities)");
    if (m < 0) return refuse("constraint " + fa + " names no coordinate");
    velocity[static_cast<std::size_t>(a)] = m == 0 ? jet.total_derivative(f) : f;
  }
  GiNaC::matrix A(static_cast<unsigned>(g), static_cast<unsigned>(n));
  std::vector<ex> b(static_cast<std::size_t>(g)), h(static_cast<std::size_t>(g));
  for (int a = 0; a < g; ++a) {
    ex linear = 0, accel = 0;
    const ex& v = velocity[static_cast<std::size_t>(a)];
    const ex Dv = jet.total_derivative(v);
    for (int j = 0; j < n; ++j) {
      const ex aj = partial_derivative(v, GiNaC::ex_to<GiNaC::symbol>(jet.q(j, 1)));
      if (jet.highest_coordinate_order(aj) > 0)
        return refuse("constraint f" + std::to_string(a + 1) + " is not linear in the velocities (df" +
                      std::to_string(a + 1) + "/d" + base::primed_name(names[static_cast<std::size_t>(j)], 1) +
                      " depends on velocities)");
      A(static_cast<unsigned>(a), static_cast<unsigned>(j)) = aj;
      linear += aj * jet.q(j, 1);
      accel += aj * jet.q(j, 2);
    }
    b[static_cast<std::size_t>(a)] = simplified_where_it_pays(v - linear);
    h[static_cast<std::size_t>(a)] = Dv - accel;
  }

  // R = K q'' + r + B^T λ.
  const int lambda_order = model.kind == ModelKind::holder ? 1 : 0;
  GiNaC::matrix K(static_cast<unsigned>(n), static_cast<unsigned>(n));
  GiNaC::matrix B(static_cast<unsigned>(g), static_cast<unsigned>(n));
  std::vector<ex> R0(static_cast<std::size_t>(n));
  GiNaC::exmap no_lambda;
  for (int a = 0; a < g; ++a) no_lambda[jet.lambda(a, lambda_order)] = 0;
  for (int i = 0; i < n; ++i) {
    const ex& R = model.equations[static_cast<std::size_t>(i)];
    for (const JetCoordinate& c : jet.jet_coordinates_in(R)) {
      if (c.kind == VariableKind::coordinate && c.order > 2)
        return refuse("R_" + names[static_cast<std::size_t>(i)] + " holds " +
                      base::primed_name(names[static_cast<std::size_t>(c.index)], c.order) +
                      " (the multiplier-free form takes second-order equations)");
      if (c.kind == VariableKind::multiplier && c.order != lambda_order)
        return refuse("R_" + names[static_cast<std::size_t>(i)] + " holds a derivative of a multiplier");
    }
    for (int j = 0; j < n; ++j) {
      const ex k = partial_derivative(R, GiNaC::ex_to<GiNaC::symbol>(jet.q(j, 2)));
      if (jet.highest_coordinate_order(k) > 1)
        return refuse("R_" + names[static_cast<std::size_t>(i)] + " is not linear in the accelerations");
      K(static_cast<unsigned>(i), static_cast<unsigned>(j)) = k;
    }
    for (int a = 0; a < g; ++a)
      B(static_cast<unsigned>(a), static_cast<unsigned>(i)) =
          partial_derivative(R, GiNaC::ex_to<GiNaC::symbol>(jet.lambda(a, lambda_order)));
    R0[static_cast<std::size_t>(i)] = R.subs(no_lambda);
  }

  // The speeds: named, the scene's `dependent`, or the first independent constraint columns.
  const std::optional<Eigen::MatrixXd> initial_jacobian = jacobian_at_initial_point(scene, A);
  const bool evaluated = initial_jacobian.has_value();
  const Eigen::MatrixXd A0 = evaluated ? *initial_jacobian : Eigen::MatrixXd();
  std::vector<bool> is_dependent(static_cast<std::size_t>(n), false);
  if (!speeds.empty()) {
    if (static_cast<int>(speeds.size()) != n - g)
      throw InputError({flag, 0, 0}, "names " + std::to_string(speeds.size()) + " speeds; " + scene.name + " has " +
                                         std::to_string(n) + " coordinates and " + std::to_string(g) +
                                         " constraints, so " + std::to_string(n - g) + " independent speeds");
    std::vector<bool> chosen(static_cast<std::size_t>(n), false);
    for (const std::string& s : speeds) {
      const auto index =
          s.size() >= 2 && s.back() == '\'' ? jet.coordinate_index(s.substr(0, s.size() - 1)) : std::nullopt;
      if (!index)
        throw InputError({flag, 0, 0}, "'" + s + "' is not the first derivative of a coordinate (coordinates: " +
                                           join(names) + "; write x')");
      if (chosen[static_cast<std::size_t>(*index)]) throw InputError({flag, 0, 0}, "names " + s + " twice");
      chosen[static_cast<std::size_t>(*index)] = true;
    }
    for (int j = 0; j < n; ++j) is_dependent[static_cast<std::size_t>(j)] = !chosen[static_cast<std::size_t>(j)];
    out.rule = "as requested";
  } else if (static_cast<int>(scene.dependent.size()) == g && g > 0) {
    for (int d : scene.dependent) is_dependent[static_cast<std::size_t>(d)] = true;
    out.rule = "the scene's dependent coordinates";
  } else {
    if (!evaluated)
      return refuse(
          "the constraint Jacobian df/dq' cannot be evaluated at the initial point to choose the "
          "dependent speeds; name the independent ones (--speeds)");
    const std::vector<int> columns = first_independent_columns(A0, g);
    if (static_cast<int>(columns.size()) < g)
      return refuse("the constraints' Jacobian df/dq' has rank below " + std::to_string(g) + " at the initial point");
    for (int d : columns) is_dependent[static_cast<std::size_t>(d)] = true;
    out.rule = "the first coordinates whose constraint columns are independent at the initial point";
  }
  for (int j = 0; j < n; ++j) {
    if (is_dependent[static_cast<std::size_t>(j)]) out.dependent.push_back(j);
    else {
      out.independent.push_back(j);
      out.speeds.push_back(base::primed_name(names[static_cast<std::size_t>(j)], 1));
    }
  }
  std::vector<std::string> dependent_names;
  for (int d : out.dependent) {
    dependent_names.push_back(base::primed_name(names[static_cast<std::size_t>(d)], 1));
    out.dependent_symbols.push_back(jet.q(d, 1));
  }
  out.dependent_names = dependent_names;
  if (evaluated && rank_of_columns(A0, out.dependent) < g) {
    const std::string message = "the dependent speeds " + join(dependent_names) + " cannot be solved for: df/d(" +
                                join(dependent_names) + ") is singular at the initial point";
    if (!speeds.empty()) throw InputError({flag, 0, 0}, message);
    return refuse(message);
  }

  // Subscripts name coordinates as the equations print them (C_{x,\psi}, not C_{x,psi}).
  auto tex = [](const std::string& coordinate) { return jet_symbol_latex(coordinate, VariableKind::coordinate, 0); };
  const auto ni = static_cast<unsigned>(out.independent.size());
  const auto ng = static_cast<unsigned>(g);
  // A_D [X y w_D] = −[A_I b h], A_D's entries named where large.
  GiNaC::matrix AD(ng, ng), rhs(ng, ni + 2);
  for (unsigned a = 0; a < ng; ++a) {
    for (unsigned k = 0; k < ng; ++k) {
      const std::string& d = names[static_cast<std::size_t>(out.dependent[k])];
      AD(a, k) = named(A(a, static_cast<unsigned>(out.dependent[k])), "A_" + std::to_string(a + 1) + "_" + d,
                       "A_{" + std::to_string(a + 1) + "," + tex(d) + "}");
    }
    for (unsigned k = 0; k < ni; ++k) {
      const std::string& i = names[static_cast<std::size_t>(out.independent[k])];
      rhs(a, k) = -named(A(a, static_cast<unsigned>(out.independent[k])), "A_" + std::to_string(a + 1) + "_" + i,
                         "A_{" + std::to_string(a + 1) + "," + tex(i) + "}");
    }
    rhs(a, ni) = -b[a];
    rhs(a, ni + 1) = -named(h[a], "h_" + std::to_string(a + 1), "h_{" + std::to_string(a + 1) + "}");
  }
  GiNaC::matrix XY;
  try {
    XY = solve(AD, rhs);
  } catch (const std::exception& e) {
    return refuse("df/d(" + join(dependent_names) + ") is singular: " + e.what());
  }
  // C: n × |I|, w: n.
  std::vector<std::vector<ex>> C(static_cast<std::size_t>(n), std::vector<ex>(ni, ex(0)));
  std::vector<ex> w(static_cast<std::size_t>(n), ex(0));
  for (unsigned k = 0; k < ni; ++k) C[static_cast<std::size_t>(out.independent[k])][k] = 1;
  for (unsigned r = 0; r < ng; ++r) {
    const int d = out.dependent[r];
    const std::string& dn = names[static_cast<std::size_t>(d)];
    ex speed = 0;
    for (unsigned k = 0; k < ni; ++k) {
      const std::string& in = names[static_cast<std::size_t>(out.independent[k])];
      C[static_cast<std::size_t>(d)][k] = named(XY(r, k), "C_" + dn + "_" + in, "C_{" + tex(dn) + "," + tex(in) + "}");
      speed += C[static_cast<std::size_t>(d)][k] * jet.q(out.independent[k], 1);
    }
    speed += XY(r, ni);
    out.dependent_speeds.push_back(simplified_where_it_pays(speed));
    w[static_cast<std::size_t>(d)] = named(XY(r, ni + 1), "w_" + dn, "w_{" + tex(dn) + "}");
  }

  // M_r = −C^T K C, f_r = C^T (R0 + K (w − q'')).
  // r = R0 − K q'' first: R0's terms in q'' are those K q'' gives back, so they cancel as the sum
  // is formed and f_r reads without accelerations (not m (w_y + y'') − m y'').
  std::vector<ex> r(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    ex e = R0[static_cast<std::size_t>(j)];
    for (int k = 0; k < n; ++k) e -= K(static_cast<unsigned>(j), static_cast<unsigned>(k)) * jet.q(k, 2);
    r[static_cast<std::size_t>(j)] = e;
  }
  std::vector<ex> residual(static_cast<std::size_t>(n));  // r + K w
  for (int j = 0; j < n; ++j) {
    ex e = r[static_cast<std::size_t>(j)];
    for (int k = 0; k < n; ++k) {
      const ex& Kjk = K(static_cast<unsigned>(j), static_cast<unsigned>(k));
      if (!Kjk.is_zero() && !w[static_cast<std::size_t>(k)].is_zero()) e += Kjk * w[static_cast<std::size_t>(k)];
    }
    residual[static_cast<std::size_t>(j)] = e;
  }
  out.mass_matrix = GiNaC::matrix(ni, ni);
  for (unsigned p = 0; p < ni; ++p) {
    for (unsigned q = 0; q < ni; ++q) {
      ex m = 0;
      for (int j = 0; j < n; ++j) {
        const ex& cj = C[static_cast<std::size_t>(j)][p];
        if (cj.is_zero()) continue;
        for (int k = 0; k < n; ++k) {
          const ex& ck = C[static_cast<std::size_t>(k)][q];
          const ex& Kjk = K(static_cast<unsigned>(j), static_cast<unsigned>(k));
          if (!ck.is_zero() && !Kjk.is_zero()) m -= cj * Kjk * ck;
        }
      }
      out.mass_matrix(p, q) = simplified_where_it_pays(m);
    }
    ex f = 0;
    for (int j = 0; j < n; ++j)
      if (!C[static_cast<std::size_t>(j)][p].is_zero())
        f += C[static_cast<std::size_t>(j)][p] * residual[static_cast<std::size_t>(j)];
    out.forcing.push_back(simplified_where_it_pays(f));
  }

  // The multipliers: B_D^T λ = −(r + K q''_sub)_D, q''_sub = C u' + w (u' = q_I'').
  std::vector<ex> accel(static_cast<std::size_t>(n), ex(0));  // q''_sub
  for (int k = 0; k < n; ++k) accel[static_cast<std::size_t>(k)] = jet.q(k, 2);
  for (unsigned row = 0; row < ng; ++row) {
    const int d = out.dependent[row];
    ex e = w[static_cast<std::size_t>(d)];
    for (unsigned k = 0; k < ni; ++k) e += C[static_cast<std::size_t>(d)][k] * jet.q(out.independent[k], 2);
    accel[static_cast<std::size_t>(d)] = e;
  }
  GiNaC::matrix BT(ng, ng), lrhs(ng, 1);
  for (unsigned row = 0; row < ng; ++row) {
    const int d = out.dependent[row];
    ex e = r[static_cast<std::size_t>(d)];
    for (int k = 0; k < n; ++k) {
      const ex& Kdk = K(static_cast<unsigned>(d), static_cast<unsigned>(k));
      if (!Kdk.is_zero()) e += Kdk * accel[static_cast<std::size_t>(k)];
    }
    lrhs(row, 0) = -e;
    for (unsigned a = 0; a < ng; ++a) BT(row, a) = B(a, static_cast<unsigned>(d));
  }
  try {
    const GiNaC::matrix lambda = solve(BT, lrhs);
    for (unsigned a = 0; a < ng; ++a) {
      out.multipliers.push_back(simplified_where_it_pays(lambda(a, 0)));
      out.multiplier_names.push_back(base::primed_name(jet.multiplier_name(static_cast<int>(a)), lambda_order));
    }
  } catch (const std::exception& e) {
    return refuse(std::string("the multipliers' coefficients are singular: ") + e.what());
  }
  out.available = true;
  return out;
}

}  // namespace nhc
