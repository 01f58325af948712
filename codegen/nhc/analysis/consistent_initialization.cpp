#include "nhc/analysis/consistent_initialization.hpp"

#include "nhc/base/number_text.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <sstream>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/expr/numeric_program.hpp"
#include "nhc/analysis/system_jacobian.hpp"
#include "nhc/expr/expression_printer.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/base/constraint_solver.hpp"
#include "nhc/base/initial_point.hpp"

namespace nhc {

std::string to_string(ValueSource source) {
  switch (source) {
    case ValueSource::given:
      return "given";
    case ValueSource::solved:
      return "solved";
    case ValueSource::repaired:
      return "repaired";
    case ValueSource::defaulted:
      return "defaulted";
    case ValueSource::computed:
      return "computed";
  }
  return "?";
}

namespace {

std::string number(double v) { return base::number_text(v, 10); }

/// Evaluation of a vector of expressions and their Jacobian in a list of jet variables, with
/// the other symbols fixed by a base substitution. Both are lowered once into NumericProgram's
/// instruction lists, whose inputs are the symbols the point assigns (in its map order), and
/// evaluated in doubles at every Newton step: over named intermediates GiNaC's substitution
/// would rewalk every tree per evaluation (the Whipple bicycle's consistent point took most of
/// a linearization sweep's time that way).
class Evaluator {
 public:
  Evaluator(std::vector<GiNaC::ex> functions, std::vector<std::string> names, std::vector<GiNaC::ex> variables)
      : f_(std::move(functions)), names_(std::move(names)), vars_(std::move(variables)) {
    // Sparse Jacobian: f_i is differentiated only by the variables that occur in it, so the
    // work is linear in the size of the constraints rather than in (functions × variables).
    std::map<GiNaC::ex, std::size_t, GiNaC::ex_is_less> column;
    for (std::size_t k = 0; k < vars_.size(); ++k) column[vars_[k]] = k;
    for (const auto& f : f_) {
      std::set<std::size_t> occurring;
      for (const GiNaC::ex& symbol : symbols_through(f))  // through named intermediates
        if (const auto c = column.find(symbol); c != column.end()) occurring.insert(c->second);
      std::vector<std::pair<std::size_t, GiNaC::ex>> row;
      for (std::size_t k : occurring) {
        GiNaC::ex d = partial_derivative(f, GiNaC::ex_to<GiNaC::symbol>(vars_[k]));
        if (!d.is_zero()) row.emplace_back(k, d);
      }
      jac_.push_back(std::move(row));
    }
  }
  GiNaC::exmap point(const GiNaC::exmap& base, const Eigen::VectorXd& x) const {
    GiNaC::exmap m = base;
    for (std::size_t k = 0; k < vars_.size(); ++k) m[vars_[k]] = x(static_cast<Eigen::Index>(k));
    return m;
  }
  Eigen::VectorXd values(const GiNaC::exmap& p) const {
    const std::vector<double> v = programs(p).values.evaluate(inputs_at(p), "a constraint at t0");
    return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
  }
  Eigen::SparseMatrix<double> sparse_jacobian(const GiNaC::exmap& p) const {
    const std::vector<double> v = programs(p).jacobian.evaluate(inputs_at(p), "a constraint's derivative at t0");
    std::vector<Eigen::Triplet<double>> triplets;
    std::size_t next = 0;
    for (std::size_t i = 0; i < f_.size(); ++i)
      for (const auto& entry : jac_[i])
        triplets.emplace_back(static_cast<int>(i), static_cast<int>(entry.first), v[next++]);
    Eigen::SparseMatrix<double> out(static_cast<Eigen::Index>(f_.size()), static_cast<Eigen::Index>(vars_.size()));
    out.setFromTriplets(triplets.begin(), triplets.end());
    return out;
  }
  Eigen::MatrixXd jacobian(const GiNaC::exmap& p) const { return Eigen::MatrixXd(sparse_jacobian(p)); }

 private:
  struct Programs {
    NumericProgram values, jacobian;
  };

  /// The programs for points that assign the symbols of p; built at the first evaluation (and
  /// again should a point assign other symbols).
  const Programs& programs(const GiNaC::exmap& p) const {
    std::vector<GiNaC::ex> symbols;
    symbols.reserve(p.size());
    for (const auto& assignment : p) symbols.push_back(assignment.first);
    const bool same = programs_ && symbols.size() == inputs_.size() &&
                      std::equal(symbols.begin(), symbols.end(), inputs_.begin(),
                                 [](const GiNaC::ex& a, const GiNaC::ex& b) { return a.is_equal(b); });
    if (same) return *programs_;
    auto built = std::make_unique<Programs>(Programs{NumericProgram(symbols), NumericProgram(symbols)});
    for (std::size_t i = 0; i < f_.size(); ++i) {
      built->values.add(f_[i], names_[i] + " at t0");
      for (const auto& entry : jac_[i]) built->jacobian.add(entry.second, "the derivative of " + names_[i] + " at t0");
    }
    inputs_ = std::move(symbols);
    programs_ = std::move(built);
    return *programs_;
  }
  /// The point's values in the programs' input order (the map's order).
  std::vector<double> inputs_at(const GiNaC::exmap& p) const {
    std::vector<double> values;
    values.reserve(p.size());
    for (const auto& [symbol, value] : p)
      values.push_back(GiNaC::is_a<GiNaC::numeric>(value)
                           ? GiNaC::ex_to<GiNaC::numeric>(value).to_double()
                           : evaluate_real(value, {}, "the value of " + to_text(symbol)));
    return values;
  }

  std::vector<GiNaC::ex> f_;
  std::vector<std::string> names_;
  std::vector<GiNaC::ex> vars_;
  std::vector<std::vector<std::pair<std::size_t, GiNaC::ex>>> jac_;  ///< nonzero ∂f_i/∂v_k per row
  mutable std::vector<GiNaC::ex> inputs_;
  mutable std::unique_ptr<Programs> programs_;
};

/// Where the violated constraint is a rolling constraint of a contact with on_slip = "slide",
/// the sentence saying so: such a motion starts sliding (docs/contacts.md, "Sliding"), which
/// `nhc simulate` follows with the sliding model, while the analysis is of the rolling one.
std::string sliding_start(const Scene& scene, int constraint) {
  if (constraint < 0) return "";
  for (const SceneContact& c : scene.contacts)
    if (c.on_slip == SlipAction::slide && std::find(c.rolling.begin(), c.rolling.end(), constraint) != c.rolling.end())
      return ". f" + std::to_string(constraint + 1) + " is a rolling constraint of the contact '" + c.name +
             "' (on_slip = \"slide\"): the contact starts sliding, which nhc simulate follows with the sliding "
             "model (docs/contacts.md); this analysis is of the rolling model";
  return "";
}

}  // namespace

std::vector<InitialValueConstraint> initial_value_constraints(const StructuralAnalysis& a,
                                                              std::vector<std::string>* notes) {
  const DaeSystem& sys = a.system;
  const JetSpace& jet = *sys.jet;
  std::vector<InitialValueConstraint> out;
  // The equations are R_q for each coordinate, then f1, f2, … (dae_system_of).
  for (const HiddenConstraint& h : a.hidden_constraints)
    out.push_back({differentiated_equation(a, h.equation, h.order), h.name, false,
                   h.equation >= jet.coordinate_count() ? h.equation - jet.coordinate_count() : -1});
  // suslov: the motion keeps f^α = 0 only if it starts on it (Suslov's equations have the
  // constraints as invariants), so the initial values must satisfy them too.
  const auto column_of_unknown = unknown_columns(sys);
  for (std::size_t m = 0; m < sys.monitored_constraints.size(); ++m) {
    const GiNaC::ex& f = sys.monitored_constraints[m];
    bool initial_data_only = true;
    for (const JetCoordinate& c : jet.jet_coordinates_in(f)) {
      const auto column = column_of_unknown.find({c.kind, c.index});
      if (column != column_of_unknown.end() && c.order >= a.d(column->second)) initial_data_only = false;
    }
    const std::string& name = sys.monitored_constraint_names[m];
    if (initial_data_only) out.push_back({f, name, true, static_cast<int>(m)});
    else if (notes)
      notes->push_back("the monitored constraint " + name + " involves derivatives the " + to_string(sys.model) +
                       " equations determine, so it is not imposed on the initial values");
  }
  return out;
}

ConsistentPoint consistent_initial_point(const Scene& scene, const StructuralAnalysis& a,
                                         const InitializationOptions& options) {
  a.require_nonsingular();
  const DaeSystem& sys = a.system;
  const JetSpace& jet = *sys.jet;
  const std::string model = to_string(sys.model);
  ConsistentPoint result;
  result.t0 = scene.initial.t0;

  GiNaC::exmap base = scene.parameter_substitution();
  base[jet.time()] = scene.initial.t0;
  for (const auto& [input, value] : scene.input_substitution(scene.initial.t0)) base[input] = value;

  auto given_value = [&](int j, int k) -> const double* {
    auto it = scene.initial.values.find(sys.unknowns[static_cast<std::size_t>(j)].name);
    if (it == scene.initial.values.end() || k >= static_cast<int>(it->second.size())) return nullptr;
    return &it->second[static_cast<std::size_t>(k)];
  };

  // Given values the model does not use as initial data.
  std::map<std::string, int> unknown_named;  // one lookup per given name, not a pass over all unknowns
  for (int u = 0; u < sys.size(); ++u) unknown_named[sys.unknowns[static_cast<std::size_t>(u)].name] = u;
  for (const auto& [name, vals] : scene.initial.values) {
    const auto named = unknown_named.find(name);
    const int j = named == unknown_named.end() ? -1 : named->second;
    if (j < 0) {
      result.notes.push_back(name + " is not an unknown of the " + model + " model: its initial values are ignored");
      continue;
    }
    const int d = a.d(j);
    for (int k = d; k < static_cast<int>(vals.size()); ++k) {
      const std::string what = sys.derivative_name(j, k);
      if (k == d)
        result.notes.push_back(what + " is not initial data of the " + model + " model (d_" + name + " = " +
                               std::to_string(d) + "): the given " + what + " = " +
                               number(vals[static_cast<std::size_t>(k)]) +
                               " serves only as a starting guess for solving the equations at t0");
      else
        result.notes.push_back(what + " is determined by the " + model + " equations (d_" + name + " = " +
                               std::to_string(d) + "): the given value " + number(vals[static_cast<std::size_t>(k)]) +
                               " is ignored");
    }
  }

  // Values x_j^(k), k < d_j: given ones kept, missing ones unknown (starting guess 0).
  const auto column_of_unknown = unknown_columns(sys);
  const int count = static_cast<int>(a.initial_values_needed.size());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(count);
  std::vector<GiNaC::ex> vars;
  std::vector<int> missing;
  for (int k = 0; k < count; ++k) {
    const JetCoordinate& c = a.initial_values_needed[static_cast<std::size_t>(k)];
    const int j = column_of_unknown.at({c.kind, c.index});
    InitialValue v;
    v.unknown = j;
    v.order = c.order;
    v.name = sys.derivative_name(j, c.order);
    if (const double* g = given_value(j, c.order)) {
      v.value = v.given = *g;
      v.source = ValueSource::given;
      x(k) = *g;
    } else {
      v.source = ValueSource::solved;
      missing.push_back(k);
    }
    result.values.push_back(v);
    vars.push_back(jet.symbol(c));
  }

  std::vector<GiNaC::ex> hidden;
  std::vector<std::string> hidden_names;
  std::vector<int> hidden_constraint;  // the scene's constraint each comes from, or -1
  for (const InitialValueConstraint& c : initial_value_constraints(a, &result.notes)) {
    hidden.push_back(c.expression);
    hidden_constraint.push_back(c.constraint);
    hidden_names.push_back((c.monitored ? "monitored constraint " : "hidden constraint ") + c.name);
    result.constraint_names.push_back(c.monitored ? c.name + " (monitored)" : c.name);
  }
  const Evaluator g(hidden, hidden_names, vars);
  base::ConstraintFunctions functions;
  functions.count = static_cast<int>(hidden.size());
  functions.size = count;
  functions.values = [&](const double* y, double* out) {
    Eigen::Map<Eigen::VectorXd>(out, functions.count) =
        g.values(g.point(base, Eigen::Map<const Eigen::VectorXd>(y, count)));
  };
  functions.jacobian = [&](const double* y, double* out) {
    Eigen::Map<Eigen::MatrixXd>(out, functions.count, count) =
        g.jacobian(g.point(base, Eigen::Map<const Eigen::VectorXd>(y, count)));
  };
  functions.sparse_jacobian = [&](const double* y, std::vector<base::SparseEntry>& entries) {
    const Eigen::SparseMatrix<double> jg =
        g.sparse_jacobian(g.point(base, Eigen::Map<const Eigen::VectorXd>(y, count)));
    for (Eigen::Index col = 0; col < jg.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(jg, col); it; ++it)
        entries.push_back({static_cast<int>(it.row()), static_cast<int>(col), it.value()});
  };

  // Missing values no constraint involves keep the guess 0: note them.
  {
    const Eigen::SparseMatrix<double> j0 =
        hidden.empty() ? Eigen::SparseMatrix<double>(0, count) : g.sparse_jacobian(g.point(base, x));
    std::vector<char> involved(static_cast<std::size_t>(count), 0);
    for (Eigen::Index col = 0; col < j0.outerSize(); ++col)
      for (Eigen::SparseMatrix<double>::InnerIterator it(j0, col); it; ++it)
        if (it.value() != 0.0) involved[static_cast<std::size_t>(col)] = 1;
    std::vector<std::string> defaulted;
    for (int k : missing)
      if (!involved[static_cast<std::size_t>(k)]) {
        result.values[static_cast<std::size_t>(k)].source = ValueSource::defaulted;
        defaulted.push_back(result.values[static_cast<std::size_t>(k)].name);
      }
    if (!defaulted.empty())
      result.notes.push_back(join_names(defaulted) + (defaulted.size() == 1 ? " is" : " are") +
                             " initial data of the " + model + " model but " +
                             (defaulted.size() == 1 ? "was" : "were") + " not given and no hidden constraint fixes " +
                             (defaulted.size() == 1 ? "it" : "them") + ": taken as 0");
  }

  // The missing values from the constraints, with the given ones fixed: the runtime's solver and
  // tolerance (nhc/base/constraint_solver.hpp), so that `nhc analyze` reports the point
  // `nhc simulate` starts from.
  std::vector<double> y(x.data(), x.data() + count);
  std::vector<double> scale(static_cast<std::size_t>(count), 0.0);
  for (int k : missing) scale[static_cast<std::size_t>(k)] = 1.0;
  const base::InitialPointTolerance tolerance =
      base::initial_point_tolerance(y, scene.simulate.rtol, scene.simulate.atol);
  // --repair-initial: the same rule as the runtime (base::solve_or_repair_initial_point), every
  // value free but the pinned ones ([initial] fixed) only when the given values miss.
  std::vector<double> repair_scale(static_cast<std::size_t>(count), 1.0);
  for (int k = 0; k < count; ++k)
    if (std::find(scene.initial.fixed.begin(), scene.initial.fixed.end(),
                  result.values[static_cast<std::size_t>(k)].name) != scene.initial.fixed.end())
      repair_scale[static_cast<std::size_t>(k)] = 0.0;
  const base::InitialPointSolve outcome = base::solve_or_repair_initial_point(
      functions, y.data(), scale, options.repair ? &repair_scale : nullptr, tolerance, options.max_iterations);
  base::ConstraintSolveResult solve = outcome.result;
  if (outcome.repaired) {
    if (!solve.converged())
      throw MathError("the " + model +
                      " model: no consistent initial point found near the given "
                      "values: " +
                      hidden_names[static_cast<std::size_t>(solve.worst)] + " keeps residual " +
                      number(solve.residuals[static_cast<std::size_t>(solve.worst)]));
    for (int k = 0; k < count; ++k) {
      InitialValue& v = result.values[static_cast<std::size_t>(k)];
      if (v.source == ValueSource::given && std::abs(y[static_cast<std::size_t>(k)] - v.given) > 0.0) {
        v.source = ValueSource::repaired;
        result.notes.push_back("repaired " + v.name + ": " + number(v.given) + " -> " +
                               number(y[static_cast<std::size_t>(k)]));
      }
    }
  } else if (!solve.converged()) {
    const auto worst = static_cast<std::size_t>(solve.worst);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> jg =
        g.sparse_jacobian(g.point(base, Eigen::Map<const Eigen::VectorXd>(y.data(), count)));
    base::InconsistentInitialPoint failure;
    failure.model = model;
    failure.constraint = hidden_names[worst];
    failure.residual = solve.residuals[worst];
    failure.t0 = scene.initial.t0;
    failure.tolerance = tolerance;
    failure.status = solve.status;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(jg, solve.worst); it; ++it) {
      if (it.value() == 0.0) continue;
      const InitialValue& v = result.values[static_cast<std::size_t>(it.col())];
      if (v.source == ValueSource::given) failure.given.push_back({v.name, v.given});
      else failure.free.push_back(v.name);
    }
    throw InconsistentInitialValues(base::describe(failure) + sliding_start(scene, hidden_constraint[worst]));
  }
  x = Eigen::Map<const Eigen::VectorXd>(y.data(), count);
  const Eigen::VectorXd residual = Eigen::Map<const Eigen::VectorXd>(solve.residuals.data(), functions.count);
  for (int k = 0; k < count; ++k) result.values[static_cast<std::size_t>(k)].value = x(k);
  for (Eigen::Index h = 0; h < residual.size(); ++h) result.constraint_residuals.push_back(residual(h));

  // Leading derivatives x_j^(d_j) from D^{c_i} f_i = 0 by Newton's method.
  base = g.point(base, x);
  const int n = sys.size();
  std::vector<GiNaC::ex> top, leading_vars;
  std::vector<std::string> top_names;
  Eigen::VectorXd z(n);
  for (int i = 0; i < n; ++i) {
    top.push_back(differentiated_equation(a, i, a.c(i)));
    top_names.push_back(derivative_equation_name(sys.equation_names[static_cast<std::size_t>(i)], a.c(i)));
  }
  for (int j = 0; j < n; ++j) {
    leading_vars.push_back(sys.unknown_symbol(j, a.d(j)));
    const double* guess = given_value(j, a.d(j));
    z(j) = guess ? *guess : 0.0;
    InitialValue v;
    v.unknown = j;
    v.order = a.d(j);
    v.name = sys.derivative_name(j, a.d(j));
    v.source = ValueSource::computed;
    result.leading.push_back(v);
  }
  const Evaluator f(top, top_names, leading_vars);
  for (int it = 0; it < options.max_iterations; ++it) {
    const GiNaC::exmap p = f.point(base, z);
    const Eigen::VectorXd r = f.values(p);
    Eigen::SparseMatrix<double> jz = f.sparse_jacobian(p);
    if (!(condition_number(jz).value < kSingularCondition)) break;  // the caller reports J
    Eigen::VectorXd step;
    if (n <= kExactConditionLimit) {  // small: the dense LU, as the exact condition number is dense too
      step = Eigen::MatrixXd(jz).partialPivLu().solve(-r);
    } else {
      jz.makeCompressed();
      const Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(jz);
      if (lu.info() != Eigen::Success) break;
      step = lu.solve(-r);
    }
    z += step;
    if (step.norm() <= 1e-12 * (1.0 + z.norm())) {
      result.leading_solved = true;
      break;
    }
  }
  if (result.leading_solved) {
    const Eigen::VectorXd r = f.values(f.point(base, z));
    if (r.size() > 0 && !(r.cwiseAbs().maxCoeff() <= 1e-8 * (1.0 + z.cwiseAbs().maxCoeff())))
      result.leading_solved = false;
  }
  for (int j = 0; j < n; ++j) result.leading[static_cast<std::size_t>(j)].value = z(j);
  result.point = f.point(base, z);
  if (!result.leading_solved) {
    if (condition_number(f.sparse_jacobian(result.point)).value < kSingularCondition)
      throw MathError("the " + model +
                      " model: Newton's method on the equations at t0 did not "
                      "converge for the leading derivatives " +
                      [&] {
                        std::vector<std::string> names;
                        for (const auto& v : result.leading) names.push_back(v.name);
                        return join_names(names);
                      }());
  }
  return result;
}

}  // namespace nhc
