// The symbolic half of the header emitter (model_preparation.hpp).
#include "nhc/emit/model_preparation.hpp"

#include "nhc/base/primed_name.hpp"

#include "nhc/expr/common_arguments.hpp"
#include "nhc/expr/common_factors.hpp"

#include "nhc/emit/parameter_jacobian.hpp"
#include "nhc/derive/discrete_lagrange_dalembert.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/expr/symbol_substitution.hpp"

#include <algorithm>
#include <optional>
#include <tuple>
#include <set>
#include <unordered_set>

#include "nhc/expr/cpp_printer.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/partial_derivative.hpp"

namespace nhc {

namespace {

/// For each expression, the indices k of the symbols `symbols[k]` occurring in it (sorted): the
/// partial derivatives with respect to all other symbols are zero and need not be formed. One
/// walk over each expression instead of one diff per (expression, symbol) pair keeps the
/// Jacobians of large sparse systems linear in their size.
std::vector<std::vector<int>> occurring_symbols(const std::vector<GiNaC::ex>& expressions,
                                                const std::vector<GiNaC::realsymbol>& symbols) {
  std::map<GiNaC::ex, int, GiNaC::ex_is_less> index;
  for (size_t k = 0; k < symbols.size(); ++k) index.emplace(symbols[k], static_cast<int>(k));
  std::vector<std::vector<int>> out;
  out.reserve(expressions.size());
  for (const GiNaC::ex& e : expressions) {
    std::set<int> found;
    for (const GiNaC::ex& symbol : symbols_through(e))
      if (const auto at = index.find(symbol); at != index.end()) found.insert(at->second);
    out.emplace_back(found.begin(), found.end());
  }
  return out;
}

}  // namespace

GiNaC::ex SymbolicJacobian::entry(int i, int j) const {
  const auto begin = rowind.begin() + colptr[static_cast<size_t>(j)];
  const auto end = rowind.begin() + colptr[static_cast<size_t>(j) + 1];
  const auto at = std::lower_bound(begin, end, i);
  return at != end && *at == i ? values[static_cast<size_t>(at - rowind.begin())] : GiNaC::ex(0);
}

SymbolicJacobian index1_jacobian(const Index1System& system) {
  SymbolicJacobian jac;
  const int n = system.size();
  jac.size = n;
  // rows[j]: the residuals in which y_j or y'_j occurs, increasing.
  std::vector<std::set<int>> rows(static_cast<size_t>(n));
  const auto in_y = occurring_symbols(system.residuals, system.y);
  const auto in_yp = occurring_symbols(system.residuals, system.yp);
  for (int i = 0; i < n; ++i) {
    for (int j : in_y[static_cast<size_t>(i)]) rows[static_cast<size_t>(j)].insert(i);
    for (int j : in_yp[static_cast<size_t>(i)]) rows[static_cast<size_t>(j)].insert(i);
  }
  // Each residual is differentiated only by the symbols it depends on: a derivative walks the
  // whole expression even where it is zero.
  const auto has = [](const std::vector<int>& sorted, int j) {
    return std::binary_search(sorted.begin(), sorted.end(), j);
  };
  const auto partial = [](const GiNaC::ex& f, const GiNaC::realsymbol& symbol, bool occurs) {
    return occurs ? partial_derivative(f, symbol) : GiNaC::ex(0);
  };
  jac.colptr.push_back(0);
  for (int j = 0; j < n; ++j) {
    for (int i : rows[static_cast<size_t>(j)]) {
      const GiNaC::ex& f = system.residuals[static_cast<size_t>(i)];
      const auto row = static_cast<size_t>(i), column = static_cast<size_t>(j);
      GiNaC::ex entry =
          partial(f, system.y[column], has(in_y[row], j)) + jac.cj * partial(f, system.yp[column], has(in_yp[row], j));
      if (entry.is_zero()) continue;
      jac.rowind.push_back(i);
      jac.values.push_back(entry);
    }
    jac.colptr.push_back(static_cast<int>(jac.rowind.size()));
  }
  return jac;
}

std::vector<ModelInvariant> invariants_in_states(const Scene& scene, const Index1System& system) {
  std::vector<ModelInvariant> out;
  for (const SceneQuantity& invariant : scene.invariants) {
    const GiNaC::ex rewritten = system.in_states(invariant.expression);
    const std::vector<JetCoordinate> missing = system.jet->jet_coordinates_in(rewritten);
    if (missing.empty()) {
      out.push_back({invariant.name, rewritten});
    } else if (invariant.required) {
      const JetCoordinate& c = missing.front();
      throw InputError(invariant.where, "invariant '" + invariant.name + "' uses " +
                                            jet_symbol_name(system.jet->variable_name(c.kind, c.index), c.order) +
                                            ", which the " + to_string(system.model) + " model does not compute");
    }
  }
  return out;
}

namespace {

std::string primed(const std::string& variable, int order) { return base::primed_name(variable, order); }

/// Symbol → name in scene notation: t, parameter names, x' for jet symbols, and the jet name of
/// each state symbol y[k] of `system` when given.
std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> scene_names(const JetSpace& jet, const Index1System* system) {
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names;
  names[jet.time()] = "t";
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k)
    names[jet.parameter(k)] = jet.parameters()[static_cast<size_t>(k)];
  for (const auto& [c, symbol] : jet.symbols()) names[symbol] = primed(jet.variable_name(c.kind, c.index), c.order);
  if (system)
    for (const auto& [jet_symbol, state] : system->jet_to_state)
      if (const auto c = jet.classify(jet_symbol))
        names[state] = primed(jet.variable_name(c->kind, c->index), c->order);
  return names;
}

}  // namespace

std::vector<std::string> scene_notation(const std::vector<GiNaC::ex>& expressions, const JetSpace& jet) {
  // One table of names for all: building it is linear in the jet space, not once per expression. A named
  // intermediate is printed by its name (its expression can be exponentially long written out).
  auto names = scene_names(jet, nullptr);
  for (const GiNaC::ex& d : intermediates_in_order(expressions))
    names[d] = GiNaC::ex_to<Intermediate>(d).intermediate_name();
  ExpressionDag dag(std::move(names));
  std::vector<std::string> printed;
  for (const GiNaC::ex& e : expressions) printed.push_back(print_cpp_expression(dag, dag.add(e)));
  return printed;
}

std::vector<SingularQuantity> singular_quantities(const Index1System& system) {
  auto depends_on = [](const GiNaC::ex& e, const std::vector<GiNaC::realsymbol>& symbols) {
    const auto through = symbols_through(e);
    return std::any_of(symbols.begin(), symbols.end(),
                       [&](const GiNaC::realsymbol& s) { return through.count(s) > 0; });
  };
  // Lowered into a DAG of their own: it names them in scene notation, removes duplicates and
  // gives them an order that does not depend on GiNaC's (run-dependent) term order.
  ExpressionDag dag(scene_names(*system.jet, &system));
  std::map<std::pair<std::uint64_t, int>, GiNaC::ex> found;
  auto consider = [&](const GiNaC::ex& base) {
    if (!depends_on(base, system.y) || depends_on(base, system.yp)) return;
    const int id = dag.add(base);
    found.emplace(std::make_pair(dag[id].key, id), base);
  };
  std::vector<GiNaC::ex> sources = system.residuals;
  sources.insert(sources.end(), system.hidden_constraints.begin(), system.hidden_constraints.end());
  // The expressions of the intermediates they use hold radicals and logarithms too.
  for (const GiNaC::ex& d : intermediates_in_order(sources))
    sources.push_back(GiNaC::ex_to<Intermediate>(d).expression());
  for (const GiNaC::ex& e : sources)
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
      const GiNaC::ex& sub = *it;
      if (GiNaC::is_exactly_a<GiNaC::power>(sub) && GiNaC::is_exactly_a<GiNaC::numeric>(sub.op(1))) {
        const GiNaC::ex power_of = sub.op(1);  // held: ex_to gives a reference into it
        const auto& exponent = GiNaC::ex_to<GiNaC::numeric>(power_of);
        if (exponent.is_negative() || !exponent.is_integer()) consider(sub.op(0));
      } else if (GiNaC::is_a<GiNaC::function>(sub) && GiNaC::ex_to<GiNaC::function>(sub).get_name() == "log") {
        consider(sub.op(0));
      }
    }
  std::vector<SingularQuantity> out;
  for (const auto& [key, expression] : found) out.push_back({print_cpp_expression(dag, key.second), expression});
  return out;
}

std::vector<SingularQuantity> euler_angle_monitors(const Scene& scene, const Index1System& system) {
  std::vector<SingularQuantity> out;
  for (const EulerChain& chain : scene.euler_chains) {
    const GiNaC::ex determinant = system.in_states(chain.determinant);
    if (!system.jet->jet_coordinates_in(determinant).empty()) continue;  // an angle that is not a state
    std::string name = "Euler angles ";
    for (std::size_t k = 0; k < chain.angles.size(); ++k) name += (k ? ", " : "") + chain.angles[k];
    name += " (" + chain.axes + "), singular at " + chain.angles[1] + " = " + chain.zeros;
    out.push_back({name, determinant});
  }
  return out;
}

namespace {

/// The scene's parameters occurring in `expressions` (through named intermediates), by index
/// in scene order.
std::vector<int> parameters_in(const std::vector<GiNaC::ex>& expressions, const JetSpace& jet) {
  std::unordered_set<GiNaC::ex, std::hash<GiNaC::ex>, GiNaC::ex_is_equal> seen;
  std::set<GiNaC::ex, GiNaC::ex_is_less> symbols;
  for (const GiNaC::ex& e : expressions) {
    if (!seen.insert(e).second) continue;
    const auto through = symbols_through(e);  // through named intermediates
    symbols.insert(through.begin(), through.end());
  }
  std::vector<int> read;
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k)
    if (symbols.count(jet.parameter(k))) read.push_back(k);
  return read;
}

/// The inputs of generated functions by their C++ names.
std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> function_inputs(const Index1System& system,
                                                                    const std::vector<int>& parameters,
                                                                    const GiNaC::realsymbol& cj,
                                                                    const DiscreteLagrangeDAlembert* step,
                                                                    const ReducedForm* reduced) {
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> in;
  if (reduced) {  // Reduced-form additions: q and the independent speeds u = q_I'
    const JetSpace& jet = *system.jet;
    for (int j = 0; j < jet.coordinate_count(); ++j) in[jet.q(j, 0)] = "q[" + std::to_string(j) + "]";
    for (std::size_t k = 0; k < reduced->independent.size(); ++k)
      in[jet.q(reduced->independent[k], 1)] = "u[" + std::to_string(k) + "]";
  }
  if (step) {  // Variational additions (docs/generated-code.md)
    in[step->h] = "h";
    in[step->w] = "impulse_weight";
    const auto name = [&](const std::vector<GiNaC::realsymbol>& symbols, const std::string& array) {
      for (std::size_t k = 0; k < symbols.size(); ++k) in[symbols[k]] = array + "[" + std::to_string(k) + "]";
    };
    name(step->increment_previous, "dq_previous");
    name(step->q, "q");
    name(step->momentum_in, "m");
    name(step->x, "x");
  }
  in[system.jet->time()] = "t";
  for (std::size_t k = 0; k < parameters.size(); ++k)
    in[system.jet->parameter(parameters[k])] = "p[" + std::to_string(k) + "]";
  // The inputs after the parameters (docs/generated-code.md, "Input additions").
  for (std::size_t k = 0; k < system.jet->inputs().size(); ++k)
    in[system.jet->input(static_cast<int>(k))] = "p[" + std::to_string(parameters.size() + k) + "]";
  for (size_t k = 0; k < system.y.size(); ++k) in[system.y[k]] = "y[" + std::to_string(k) + "]";
  for (size_t k = 0; k < system.yp.size(); ++k) in[system.yp[k]] = "yp[" + std::to_string(k) + "]";
  in[cj] = "cj";
  return in;
}

const std::vector<std::pair<std::string, std::string>> kStateInputs = {
    {"double", "t"}, {"const double*", "y"}, {"const double*", "yp"}, {"const double*", "p"}};

std::string name_or_empty(const std::vector<std::string>& names, size_t i) {
  return i < names.size() ? sanitize_comment(names[i]) : "";
}

FunctionPlan residual_function(const Index1System& system, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "residual";
  f.doc = "/// F(t, y, y') = 0, IDA form; r has n_states entries.\n";
  f.parameters = kStateInputs;
  f.parameters.push_back({"double*", "r"});
  for (size_t i = 0; i < system.residuals.size(); ++i)
    f.assignments.push_back(
        {"r[" + std::to_string(i) + "]", dag.add(system.residuals[i]), name_or_empty(system.residual_names, i)});
  return f;
}

/// J = dF/dy + cj dF/dy': dense column-major, or the compressed-column values.
FunctionPlan jacobian_function(const SymbolicJacobian& jacobian, bool dense, ExpressionDag& dag) {
  FunctionPlan f;
  f.parameters = {
      {"double", "t"}, {"const double*", "y"}, {"const double*", "yp"}, {"double", "cj"}, {"const double*", "p"}};
  if (dense) {
    f.name = "jacobian";
    f.doc = "/// J = dF/dy + cj dF/dy', column-major n_states x n_states.\n";
    f.parameters.push_back({"double*", "J"});
    f.prologue = "  for (int k = 0; k < n_states * n_states; ++k) J[k] = 0.0;\n";
    f.zero_fill = jacobian.size * jacobian.size;
  } else {
    f.name = "jacobian_values";
    f.doc =
        "/// Nonzero values of J = dF/dy + cj dF/dy' in compressed-column order\n"
        "/// (jacobian_colptr, jacobian_rowind).\n";
    f.parameters.push_back({"double*", "values"});
  }
  const size_t n = static_cast<size_t>(jacobian.size);
  for (size_t j = 0; j < n; ++j)
    for (int k = jacobian.colptr[j]; k < jacobian.colptr[j + 1]; ++k) {
      const int i = jacobian.rowind[static_cast<size_t>(k)];
      const size_t at = static_cast<size_t>(i) + j * n;
      const std::string target = dense ? "J[" + std::to_string(at) + "]" : "values[" + std::to_string(k) + "]";
      f.assignments.push_back({target, dag.add(jacobian.values[static_cast<size_t>(k)]),
                               "(" + std::to_string(i) + ", " + std::to_string(j) + ")"});
    }
  return f;
}

FunctionPlan hidden_constraints_function(const Index1System& system, ExpressionDag& dag) {
  FunctionPlan g;
  g.name = "hidden_constraints";
  g.doc =
      "/// Hidden constraints g(t, y) = 0 (derivatives of the equations the index-1 form\n"
      "/// differentiated away); they fix consistent initial values and drift during\n"
      "/// integration.\n";
  g.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}, {"double*", "g"}};
  for (size_t i = 0; i < system.hidden_constraints.size(); ++i)
    g.assignments.push_back({"g[" + std::to_string(i) + "]", dag.add(system.hidden_constraints[i]),
                             name_or_empty(system.hidden_constraint_names, i)});
  return g;
}

/// G = dg/dy from the Jacobian the index-1 reduction already formed (Index1System).
FunctionPlan hidden_constraints_jacobian_function(const Index1System& system, ExpressionDag& dag) {
  FunctionPlan G;
  G.name = "hidden_constraints_jacobian";
  G.doc = "/// G = dg/dy, column-major n_hidden x n_states.\n";
  G.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}, {"double*", "G"}};
  G.prologue = "  for (int k = 0; k < n_hidden * n_states; ++k) G[k] = 0.0;\n";
  G.zero_fill = static_cast<int>(system.hidden_constraints.size() * system.states.size());
  const size_t h = system.hidden_constraints.size();
  if (system.hidden_constraint_jacobian.size() != h)
    throw MathError("index-1 system without the Jacobian of its hidden constraints");
  // Column-major order (k, then r), as the dense G is laid out.
  std::vector<std::tuple<size_t, size_t, const GiNaC::ex*>> entries;
  for (size_t r = 0; r < h; ++r)
    for (const auto& [k, value] : system.hidden_constraint_jacobian[r])
      entries.emplace_back(static_cast<size_t>(k), r, &value);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  for (const auto& [k, r, entry] : entries)
    if (!entry->is_zero())
      G.assignments.push_back({"G[" + std::to_string(r + h * k) + "]", dag.add(*entry),
                               "(" + std::to_string(r) + ", " + std::to_string(k) + ")"});
  return G;
}

FunctionPlan invariants_function(const std::vector<ModelInvariant>& invariants, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "invariants";
  f.doc = "/// The scene's invariants I(t, y, y'), in invariant_names order.\n";
  f.parameters = kStateInputs;
  f.parameters.push_back({"double*", "out"});
  for (size_t i = 0; i < invariants.size(); ++i)
    f.assignments.push_back(
        {"out[" + std::to_string(i) + "]", dag.add(invariants[i].in_states), sanitize_comment(invariants[i].name)});
  return f;
}

FunctionPlan reference_function(const SceneReference::Entries& reference, const Index1System& system,
                                ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "reference";
  f.doc = "/// The scene's reference solution q_c(t) for the coordinates reference_coordinate.\n";
  f.parameters = {{"double", "t"}, {"const double*", "p"}, {"double*", "q"}};
  for (size_t i = 0; i < reference.size(); ++i) {
    const auto& [coordinate, expression] = reference[i];
    f.assignments.push_back({"q[" + std::to_string(i) + "]", dag.add(expression),
                             sanitize_comment(system.jet->coordinates().at(static_cast<size_t>(coordinate)))});
  }
  return f;
}

/// The inputs' default signals u_k(t, p), the values a run uses unless it sets its own.
FunctionPlan default_inputs_function(const std::vector<SceneInput>& inputs, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "default_inputs";
  f.doc =
      "/// The inputs' default signals u(t), in input_names order (what p[n_parameters + k] holds\n"
      "/// unless the application sets the input).\n";
  f.parameters = {{"double", "t"}, {"const double*", "p"}, {"double*", "u"}};
  for (size_t k = 0; k < inputs.size(); ++k)
    f.assignments.push_back(
        {"u[" + std::to_string(k) + "]", dag.add(inputs[k].default_signal), sanitize_comment(inputs[k].name)});
  return f;
}

/// Singular-set monitors (runtime additions): quantities whose zeros make the residual or the
/// hidden constraints non-smooth; the runtime watches them as root functions.
FunctionPlan singular_quantities_function(const std::vector<SingularQuantity>& singular, bool euler_angles,
                                          ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "singular_quantities";
  f.doc =
      "/// Quantities that vanish where the equations are singular (bases of square roots,\n"
      "/// of negative powers and arguments of logarithms), in singular_names order.\n";
  if (euler_angles)
    f.doc +=
        "/// The \"Euler angles\" ones: sin or cos of the middle angle, zero where the angular\n"
        "/// velocity does not determine the angle rates (watched only to explain a failure).\n";
  f.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}, {"double*", "s"}};
  for (size_t i = 0; i < singular.size(); ++i)
    f.assignments.push_back({"s[" + std::to_string(i) + "]", dag.add(singular[i].expression), ""});
  return f;
}

/// dF/dp or dg/dp as a column-major rows × n_parameters matrix, zero-filled, its structural
/// nonzeros assigned (parameter_jacobian.hpp).
FunctionPlan parameter_matrix_function(const std::string& name, const std::string& doc, const std::string& out,
                                       int rows, int n_parameters, const std::vector<GiNaC::ex>& entries,
                                       const std::vector<int>& nonzeros,
                                       std::vector<std::pair<std::string, std::string>> inputs, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = name;
  f.doc = doc;
  f.parameters = std::move(inputs);
  f.parameters.push_back({"double*", out});
  f.prologue = "  for (int k = 0; k < " + std::to_string(rows * n_parameters) + "; ++k) " + out + "[k] = 0.0;\n";
  f.zero_fill = rows * n_parameters;
  for (int at : nonzeros)
    f.assignments.push_back({out + "[" + std::to_string(at) + "]", dag.add(entries[static_cast<size_t>(at)]),
                             "(" + std::to_string(at % rows) + ", " + std::to_string(at / rows) + ")"});
  return f;
}

/// The continuous momentum ∂L/∂q'(t, y): the variational integrator's first discrete momentum.
FunctionPlan momentum_function(const DiscreteLagrangeDAlembert& step, const Index1System& system, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "momentum";
  f.doc = "/// The momentum dL/dq'(t, y), one per coordinate (Variational additions).\n";
  f.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}, {"double*", "m"}};
  for (std::size_t i = 0; i < step.momentum.size(); ++i)
    f.assignments.push_back({"m[" + std::to_string(i) + "]", dag.add(system.in_states(step.momentum[i])),
                             sanitize_comment(system.jet->coordinates().at(i))});
  return f;
}

const std::vector<std::pair<std::string, std::string>> kStepInputs = {
    {"double", "t"},        {"double", "h"},        {"double", "impulse_weight"}, {"const double*", "dq_previous"},
    {"const double*", "q"}, {"const double*", "m"}, {"const double*", "x"},       {"const double*", "p"}};

/// The discrete Lagrange–d'Alembert residual in x = (Δq_k, λ_k) (discrete_lagrange_dalembert.hpp).
FunctionPlan variational_residual_function(const DiscreteLagrangeDAlembert& step, const Index1System& system,
                                           ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "variational_residual";
  f.doc =
      "/// The discrete Lagrange-d'Alembert step r(x) = 0 in x = (q_{k+1} - q_k, lambda_k), n_coordinates +\n"
      "/// n_multipliers entries (docs/variational.md).\n";
  f.parameters = kStepInputs;
  f.parameters.push_back({"double*", "r"});
  const int n = system.jet->coordinate_count();
  for (std::size_t i = 0; i < step.residual.size(); ++i) {
    const int k = static_cast<int>(i);
    const std::string name = k < n ? "R_" + system.jet->coordinates().at(i) : "f" + std::to_string(k - n + 1);
    f.assignments.push_back({"r[" + std::to_string(i) + "]", dag.add(step.residual[i]), sanitize_comment(name)});
  }
  return f;
}

/// dr/dx of the step, column-major, zero-filled; only the entries whose x_j occurs are formed.
FunctionPlan variational_jacobian_function(const DiscreteLagrangeDAlembert& step, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "variational_jacobian";
  f.doc = "/// dr/dx of variational_residual, column-major (n_coordinates + n_multipliers)^2.\n";
  f.parameters = kStepInputs;
  f.parameters.push_back({"double*", "J"});
  const std::size_t size = step.x.size();
  f.prologue = "  for (int k = 0; k < " + std::to_string(size * size) + "; ++k) J[k] = 0.0;\n";
  f.zero_fill = size * size;
  const auto occurring = occurring_symbols(step.residual, step.x);
  std::vector<std::tuple<std::size_t, std::size_t, GiNaC::ex>> entries;  // (column, row, value)
  for (std::size_t i = 0; i < size; ++i)
    for (int j : occurring[i]) {
      const GiNaC::ex value = partial_derivative(step.residual[i], step.x[static_cast<std::size_t>(j)]);
      if (!value.is_zero()) entries.emplace_back(static_cast<std::size_t>(j), i, value);
    }
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  for (const auto& [j, i, value] : entries)
    f.assignments.push_back({"J[" + std::to_string(i + size * j) + "]", dag.add(value),
                             "(" + std::to_string(i) + ", " + std::to_string(j) + ")"});
  return f;
}

/// m_{k+1} after a step.
FunctionPlan variational_momentum_function(const DiscreteLagrangeDAlembert& step, const Index1System& system,
                                           ExpressionDag& dag) {
  FunctionPlan f;
  f.name = "variational_momentum";
  f.doc = "/// The discrete momentum m_{k+1} at q_{k+1} after the step from q_k to x.\n";
  f.parameters = {{"double", "t"},        {"double", "h"},        {"const double*", "q"},
                  {"const double*", "x"}, {"const double*", "p"}, {"double*", "m_next"}};
  for (std::size_t i = 0; i < step.momentum_out.size(); ++i)
    f.assignments.push_back({"m_next[" + std::to_string(i) + "]", dag.add(step.momentum_out[i]),
                             sanitize_comment(system.jet->coordinates().at(i))});
  return f;
}

const std::vector<std::pair<std::string, std::string>> kSpeedInputs = {
    {"double", "t"}, {"const double*", "q"}, {"const double*", "u"}, {"const double*", "p"}};

/// The reduced form's expressions in (t, q, u, p): the dependent speeds replaced by X u + y, and
/// the accelerations, which f_r is written over but does not depend on (reduced_form.hpp), by 0.
struct ReducedFunctions {
  std::vector<GiNaC::ex> velocities, mass_matrix, forcing;  ///< mass_matrix column-major
};
ReducedFunctions reduced_functions(const ReducedForm& reduced, const JetSpace& jet) {
  // X u + y may hold the dependent speeds through named intermediates (y from b = v − A q', which
  // does not depend on q' but need not cancel symbolically): there they are set to 0, exactly.
  GiNaC::exmap map;
  for (int j = 0; j < jet.coordinate_count(); ++j) map[jet.q(j, 2)] = 0;
  for (int d : reduced.dependent) map[jet.q(d, 1)] = 0;
  const SymbolSubstitution without_dependent(map);
  for (std::size_t r = 0; r < reduced.dependent.size(); ++r)
    map[jet.q(reduced.dependent[r], 1)] = without_dependent(reduced.dependent_speeds[r]);
  const SymbolSubstitution substitute(map);
  ReducedFunctions out;
  out.velocities.resize(static_cast<std::size_t>(jet.coordinate_count()));
  for (int j : reduced.independent) out.velocities[static_cast<std::size_t>(j)] = jet.q(j, 1);
  for (std::size_t r = 0; r < reduced.dependent.size(); ++r)
    out.velocities[static_cast<std::size_t>(reduced.dependent[r])] = substitute(reduced.dependent_speeds[r]);
  const unsigned n = reduced.mass_matrix.rows();
  for (unsigned c = 0; c < n; ++c)
    for (unsigned r = 0; r < n; ++r) out.mass_matrix.push_back(substitute(reduced.mass_matrix(r, c)));
  for (const GiNaC::ex& f : reduced.forcing) out.forcing.push_back(substitute(f));
  return out;
}

/// One function of the Reduced-form additions: out[k] = values[k], zero-filled when `zero_fill`.
FunctionPlan reduced_function(const std::string& name, const std::string& doc, const std::string& out,
                              const std::vector<GiNaC::ex>& values, const std::vector<std::string>& comments,
                              bool zero_fill, ExpressionDag& dag) {
  FunctionPlan f;
  f.name = name;
  f.doc = doc;
  f.parameters = kSpeedInputs;
  f.parameters.push_back({"double*", out});
  if (zero_fill) {
    f.prologue = "  for (int k = 0; k < " + std::to_string(values.size()) + "; ++k) " + out + "[k] = 0.0;\n";
    f.zero_fill = static_cast<int>(values.size());
  }
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!zero_fill || !values[k].is_zero())
      f.assignments.push_back({out + "[" + std::to_string(k) + "]", dag.add(values[k]),
                               k < comments.size() ? sanitize_comment(comments[k]) : ""});
  return f;
}

}  // namespace

bool PreparedModel::has_function(const std::string& name) const {
  return std::any_of(functions.begin(), functions.end(), [&](const FunctionPlan& f) { return f.name == name; });
}

PreparedModel prepare_model(const Scene& scene, const Index1System& system, JacobianKind jacobian, bool sensitivities,
                            bool variational, const ReducedForm* reduced) {
  PreparedModel m;
  m.model = to_string(system.model);
  m.namespace_name = generated_namespace_name(scene.name, system.model);
  m.jacobian = jacobian;
  m.n_states = system.size();
  m.n_coordinates = system.jet->coordinate_count();
  m.n_multipliers = system.model == ModelKind::suslov ? 0 : static_cast<int>(scene.constraints.size());
  m.n_hidden = static_cast<int>(system.hidden_constraints.size());
  m.invariants = invariants_in_states(scene, system);
  m.n_invariants = static_cast<int>(m.invariants.size());
  m.reference = scene.reference.for_model(system.model);
  m.n_reference = static_cast<int>(m.reference.size());
  const bool dense = jacobian == JacobianKind::dense, sparse = jacobian == JacobianKind::sparse;
  if (dense || sparse) m.symbolic_jacobian = index1_jacobian(system);
  m.singular = singular_quantities(system);
  std::vector<SingularQuantity> euler_angles = euler_angle_monitors(scene, system);
  for (SingularQuantity& q : euler_angles) m.singular.push_back(std::move(q));
  m.n_singular = static_cast<int>(m.singular.size());
  // The Jacobians and singular quantities are derivatives and parts of these: they read no more.
  std::vector<GiNaC::ex> read(system.residuals.begin(), system.residuals.end());
  read.insert(read.end(), system.hidden_constraints.begin(), system.hidden_constraints.end());
  for (const ModelInvariant& i : m.invariants) read.push_back(i.in_states);
  for (const auto& entry : m.reference) read.push_back(entry.second);
  for (const SceneInput& u : scene.inputs) read.push_back(u.default_signal);
  // Variational additions (docs/generated-code.md): the chetaev model's discrete step.
  std::optional<DiscreteLagrangeDAlembert> step;
  if (variational) {
    step = discrete_lagrange_dalembert(scene, system.model);
    read.insert(read.end(), step->residual.begin(), step->residual.end());
  }
  m.variational = step.has_value();
  // Reduced-form additions (docs/generated-code.md): the multiplier-free form where it exists.
  if (reduced && !reduced->available) reduced = nullptr;
  std::optional<ReducedFunctions> speeds;
  if (reduced) {
    speeds = reduced_functions(*reduced, *system.jet);
    for (const auto* list : {&speeds->velocities, &speeds->mass_matrix, &speeds->forcing})
      read.insert(read.end(), list->begin(), list->end());
    m.n_speeds = static_cast<int>(reduced->independent.size());
    m.speed_coordinate = reduced->independent;
  }
  m.parameters = parameters_in(read, *system.jet);
  m.n_parameters = static_cast<int>(m.parameters.size());
  for (int k : m.parameters) m.parameter_names.push_back(system.jet->parameters().at(static_cast<std::size_t>(k)));
  m.n_inputs = static_cast<int>(scene.inputs.size());
  for (const SceneInput& u : scene.inputs) m.input_names.push_back(u.name);

  // Lowered in the order the functions are printed.
  m.dag =
      ExpressionDag(function_inputs(system, m.parameters, m.symbolic_jacobian.cj, step ? &*step : nullptr, reduced));
  m.functions.push_back(residual_function(system, m.dag));
  if (dense || sparse) m.functions.push_back(jacobian_function(m.symbolic_jacobian, dense, m.dag));
  if (m.n_hidden > 0) {
    m.functions.push_back(hidden_constraints_function(system, m.dag));
    m.functions.push_back(hidden_constraints_jacobian_function(system, m.dag));
  }
  if (m.n_invariants > 0) m.functions.push_back(invariants_function(m.invariants, m.dag));
  if (m.n_reference > 0) m.functions.push_back(reference_function(m.reference, system, m.dag));
  if (m.n_singular > 0) m.functions.push_back(singular_quantities_function(m.singular, !euler_angles.empty(), m.dag));
  if (m.n_inputs > 0) m.functions.push_back(default_inputs_function(scene.inputs, m.dag));
  // Sensitivity additions (docs/generated-code.md): only when asked for and the scene has parameters.
  m.sensitivities = sensitivities && m.n_parameters > 0;
  if (m.sensitivities) {
    const ParameterJacobian pj = parameter_jacobian(system, m.parameters, scene.inputs);
    m.functions.push_back(parameter_matrix_function(
        "residual_parameter_jacobian", "/// dF/dp, column-major n_states x n_parameters.\n", "Fp", m.n_states,
        m.n_parameters, pj.residual, pj.residual_nonzeros, kStateInputs, m.dag));
    if (m.n_hidden > 0)
      m.functions.push_back(parameter_matrix_function(
          "hidden_parameter_jacobian", "/// dg/dp of the hidden constraints, column-major n_hidden x n_parameters.\n",
          "Gp", m.n_hidden, m.n_parameters, pj.hidden, pj.hidden_nonzeros,
          {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}}, m.dag));
  }
  if (step) {
    m.functions.push_back(momentum_function(*step, system, m.dag));
    m.functions.push_back(variational_residual_function(*step, system, m.dag));
    m.functions.push_back(variational_jacobian_function(*step, m.dag));
    m.functions.push_back(variational_momentum_function(*step, system, m.dag));
  }
  if (speeds) {
    std::vector<std::string> velocity_names, mass_names;
    for (const std::string& c : system.jet->coordinates()) velocity_names.push_back(c + "'");
    for (int c = 0; c < m.n_speeds; ++c)
      for (int r = 0; r < m.n_speeds; ++r)
        mass_names.push_back("(" + std::to_string(r) + ", " + std::to_string(c) + ")");
    m.functions.push_back(reduced_function(
        "velocities", "/// q'(t, q, u): the independent speeds u and the dependent ones from them, n_coordinates.\n",
        "qp", speeds->velocities, velocity_names, false, m.dag));
    m.functions.push_back(reduced_function("mass_matrix",
                                           "/// M_r(t, q, u) of M_r u' = f_r, column-major n_speeds x n_speeds.\n", "M",
                                           speeds->mass_matrix, mass_names, true, m.dag));
    m.functions.push_back(reduced_function("forcing", "/// f_r(t, q, u) of M_r u' = f_r, n_speeds.\n", "f",
                                           speeds->forcing, reduced->speeds, false, m.dag));
  }

  // Factors common to several terms of a sum taken out (common_factors.hpp), then pairs of
  // operands common to several sums or products computed once (common_arguments.hpp).
  std::vector<int> all_outputs;
  for (const FunctionPlan& f : m.functions)
    for (const Assignment& a : f.assignments) all_outputs.push_back(a.value);
  m.dag = share_common_arguments(factor_common_terms(m.dag, all_outputs), all_outputs);
  std::size_t next = 0;
  for (FunctionPlan& f : m.functions)
    for (Assignment& a : f.assignments) a.value = all_outputs[next++];

  for (FunctionPlan& f : m.functions) {
    std::vector<int> outputs;
    for (const Assignment& a : f.assignments) outputs.push_back(a.value);
    f.before = tree_operation_count(m.dag, outputs);
    f.after = dag_operation_count(m.dag, outputs);
    m.before_cse += f.before;
    m.after_cse += f.after;
  }
  return m;
}

}  // namespace nhc
