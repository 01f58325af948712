#include "nhc/emit/header_emitter.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "nhc/emit/cpp_printer.hpp"
#include "nhc/emit/parameter_jacobian.hpp"
#include "nhc/errors.hpp"

namespace nhc {

std::string to_string(JacobianKind kind) {
  switch (kind) {
    case JacobianKind::dense: return "dense";
    case JacobianKind::sparse: return "sparse";
    case JacobianKind::none: return "none";
  }
  return "dense";
}

std::optional<JacobianKind> parse_jacobian_kind(const std::string& name) {
  for (JacobianKind k : {JacobianKind::dense, JacobianKind::sparse, JacobianKind::none})
    if (to_string(k) == name) return k;
  return std::nullopt;
}

std::string sanitize_comment(const std::string& text) {
  // Decided on the output, not the input: a replacement must not form a sequence either
  // ("\xff\xff/" would otherwise become the trigraph "??/", a line splice in C++14).
  std::string out;
  auto put = [&out](char c) {
    if (!out.empty() && ((out.back() == '*' && c == '/') || (out.back() == '?' && c == '?')))
      out += ' ';  // "* /" cannot close a comment, "? ?" is no trigraph
    out += c;
  };
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\\') put('/');  // no line splicing
    else if (c == '\n' || c == '\r' || c == '\t') put(' ');
    else if (c < 0x20 || c >= 0x7f) put('?');  // ASCII only: no U+2028, no invalid UTF-8
    else put(ch);
  }
  return out;
}

std::string cpp_string_literal(const std::string& text) {
  std::string out = "\"";
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c >= 0x7f || c == '?') {
      char octal[8];
      std::snprintf(octal, sizeof octal, "\\%03o", static_cast<unsigned>(c));
      out += octal;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

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
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (GiNaC::is_a<GiNaC::symbol>(*it))
        if (const auto at = index.find(*it); at != index.end()) found.insert(at->second);
    out.emplace_back(found.begin(), found.end());
  }
  return out;
}

}  // namespace

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
  jac.entries.assign(static_cast<size_t>(n) * static_cast<size_t>(n), GiNaC::ex(0));
  jac.colptr.push_back(0);
  for (int j = 0; j < n; ++j) {
    for (int i : rows[static_cast<size_t>(j)]) {
      const GiNaC::ex& f = system.residuals[static_cast<size_t>(i)];
      GiNaC::ex entry = f.diff(system.y[static_cast<size_t>(j)]) +
                        jac.cj * f.diff(system.yp[static_cast<size_t>(j)]);
      if (!entry.is_zero()) jac.rowind.push_back(i);
      jac.entries[static_cast<size_t>(i) + static_cast<size_t>(n) * static_cast<size_t>(j)] = entry;
    }
    jac.colptr.push_back(static_cast<int>(jac.rowind.size()));
  }
  return jac;
}

std::vector<GiNaC::ex> hidden_constraint_jacobian(const Index1System& system) {
  const size_t h = system.hidden_constraints.size();
  std::vector<GiNaC::ex> entries(h * system.y.size(), GiNaC::ex(0));
  const auto in_y = occurring_symbols(system.hidden_constraints, system.y);
  for (size_t r = 0; r < h; ++r)
    for (int j : in_y[r])
      entries[r + h * static_cast<size_t>(j)] =
          system.hidden_constraints[r].diff(system.y[static_cast<size_t>(j)]);
  return entries;
}

std::vector<GiNaC::ex> invariants_in_states(const Scene& scene, const Index1System& system) {
  std::vector<GiNaC::ex> out;
  for (const auto& [name, expression] : scene.invariants) {
    const GiNaC::ex rewritten = expression.subs(system.jet_to_state);
    for (const JetCoordinate& c : system.jet->jet_coordinates_in(rewritten))
      throw MathError("invariant " + name + " involves " +
                      jet_symbol_name(system.jet->variable_name(c.kind, c.index), c.order) +
                      ", which is not a state of the " + to_string(system.model) +
                      " model (nor the derivative of one)");
    out.push_back(rewritten);
  }
  return out;
}

namespace {

std::string primed(const std::string& variable, int order) {
  return variable + std::string(static_cast<size_t>(order), '\'');
}

/// Symbol → name in scene notation: t, parameter names, x' for jet symbols, and the jet name of
/// each state symbol y[k] of `system` when given.
std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> scene_names(const JetSpace& jet,
                                                                const Index1System* system) {
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names;
  names[jet.time()] = "t";
  for (int k = 0; k < static_cast<int>(jet.parameters().size()); ++k)
    names[jet.parameter(k)] = jet.parameters()[static_cast<size_t>(k)];
  for (const auto& [c, symbol] : jet.symbols())
    names[symbol] = primed(jet.variable_name(c.kind, c.index), c.order);
  if (system)
    for (const auto& [jet_symbol, state] : system->jet_to_state)
      if (const auto c = jet.classify(jet_symbol))
        names[state] = primed(jet.variable_name(c->kind, c->index), c->order);
  return names;
}

}  // namespace

std::string scene_notation(const GiNaC::ex& e, const JetSpace& jet) {
  ExpressionDag dag(scene_names(jet, nullptr));
  return print_cpp_expression(dag, dag.add(e));
}

std::vector<SingularQuantity> singular_quantities(const Index1System& system) {
  auto depends_on = [](const GiNaC::ex& e, const std::vector<GiNaC::realsymbol>& symbols) {
    return std::any_of(symbols.begin(), symbols.end(),
                       [&](const GiNaC::realsymbol& s) { return e.has(s); });
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
  for (const GiNaC::ex& e : sources)
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
      const GiNaC::ex& sub = *it;
      if (GiNaC::is_exactly_a<GiNaC::power>(sub) &&
          GiNaC::is_exactly_a<GiNaC::numeric>(sub.op(1))) {
        const auto& exponent = GiNaC::ex_to<GiNaC::numeric>(sub.op(1));
        if (exponent.is_negative() || !exponent.is_integer()) consider(sub.op(0));
      } else if (GiNaC::is_a<GiNaC::function>(sub) &&
                 GiNaC::ex_to<GiNaC::function>(sub).get_name() == "log") {
        consider(sub.op(0));
      }
    }
  std::vector<SingularQuantity> out;
  for (const auto& [key, expression] : found)
    out.push_back({print_cpp_expression(dag, key.second), expression});
  return out;
}

namespace {

/// The C table, identical to runtime/nhc/runtime/model_table.h; whichever is included first
/// defines it.
constexpr int kModelTableAbiVersion = 3;
constexpr const char* kModelTableDeclaration = R"(
#ifndef NHC_MODEL_TABLE_DEFINED
#define NHC_MODEL_TABLE_DEFINED
extern "C" {
struct nhc_model_table {
  int abi_version;
  const char* scene_name;
  const char* model_name;
  int n_states, n_parameters, n_coordinates, n_multipliers, n_hidden, n_invariants, n_reference;
  const char* const* state_names;
  const int* state_variable;
  const int* state_order;
  const double* differential_id;
  const char* const* parameter_names;
  const double* default_parameters;
  const char* const* hidden_names;
  const char* const* invariant_names;
  const int* reference_coordinate;
  void (*residual)(double, const double*, const double*, const double*, double*);
  void (*jacobian)(double, const double*, const double*, double, const double*, double*);
  int jacobian_nnz;
  const int* jacobian_colptr;
  const int* jacobian_rowind;
  void (*jacobian_values)(double, const double*, const double*, double, const double*, double*);
  void (*hidden_constraints)(double, const double*, const double*, double*);
  void (*hidden_constraints_jacobian)(double, const double*, const double*, double*);
  void (*invariants)(double, const double*, const double*, const double*, double*);
  void (*reference)(double, const double*, double*);
  const char* const* residual_names;
  int n_singular;
  const char* const* singular_names;
  void (*singular_quantities)(double, const double*, const double*, double*);
  void (*residual_parameter_jacobian)(double, const double*, const double*, const double*, double*);
  void (*hidden_parameter_jacobian)(double, const double*, const double*, double*);
};
}
#endif
)";

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string joined(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (size_t k = 0; k < items.size(); ++k) out += (k ? separator : "") + items[k];
  return out;
}

template <class T, class F>
std::string list_of(const std::vector<T>& items, F&& print) {
  std::vector<std::string> texts;
  for (const auto& item : items) texts.push_back(print(item));
  return "{" + joined(texts, ", ") + "}";
}

std::string describe_count(const std::string& label, const OperationCount& before,
                           const OperationCount& after) {
  char line[160];
  std::snprintf(line, sizeof line, "//   %-28s %7lld %7lld\n", label.c_str(), before.total(),
                after.total());
  return line;
}

/// One emitted function: its signature parameters, the assignments and what it may read.
struct FunctionPlan {
  std::string name;
  std::string doc;
  /// (type, name) in order; a name the body does not read is printed as a comment.
  std::vector<std::pair<std::string, std::string>> parameters;
  std::vector<Assignment> assignments;
  std::string prologue;  ///< e.g. zero fill of a dense matrix
  OperationCount before, after;
};

class HeaderWriter {
 public:
  HeaderWriter(const Scene& scene, const Index1System& system, const HeaderOptions& options)
      : scene_(scene),
        system_(system),
        options_(options),
        jacobian_(options.jacobian == JacobianKind::none ? SymbolicJacobian{}
                                                         : index1_jacobian(system)),
        dag_(inputs()) {}

  GeneratedHeader write();

 private:
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> inputs() const {
    std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> in;
    in[system_.jet->time()] = "t";
    for (int k = 0; k < static_cast<int>(system_.jet->parameters().size()); ++k)
      in[system_.jet->parameter(k)] = "p[" + std::to_string(k) + "]";
    for (size_t k = 0; k < system_.y.size(); ++k) in[system_.y[k]] = "y[" + std::to_string(k) + "]";
    for (size_t k = 0; k < system_.yp.size(); ++k)
      in[system_.yp[k]] = "yp[" + std::to_string(k) + "]";
    in[jacobian_.cj] = "cj";
    return in;
  }

  std::string function_text(FunctionPlan& plan, const std::set<std::string>& allowed);

  const Scene& scene_;
  const Index1System& system_;
  const HeaderOptions& options_;
  SymbolicJacobian jacobian_;
  ExpressionDag dag_;
};

std::string HeaderWriter::function_text(FunctionPlan& plan, const std::set<std::string>& allowed) {
  std::vector<int> outputs;
  for (const auto& a : plan.assignments) outputs.push_back(a.value);
  plan.before = tree_operation_count(dag_, outputs);
  plan.after = dag_operation_count(dag_, outputs);
  const PrintedBlock block = print_cpp_block(dag_, plan.assignments, "  ");
  for (const std::string& used : block.used_inputs)
    if (!allowed.count(used))
      throw MathError(plan.name + " of the " + to_string(system_.model) + " model of " +
                      scene_.name + " depends on " + used + ", which it does not receive");

  std::vector<std::string> parameters;
  for (const auto& [type, name] : plan.parameters) {
    const bool read = block.used_inputs.count(name) > 0 || type == "double*";
    parameters.push_back(type + " " + (read ? name : "/*" + name + "*/"));
  }
  std::string text = plan.doc;
  text += "inline void " + plan.name + "(" + joined(parameters, ", ") + ") noexcept {\n";
  text += plan.prologue;
  text += block.code;
  text += "}\n";
  return text;
}

GeneratedHeader HeaderWriter::write() {
  const int n = system_.size();
  const std::string model = to_string(system_.model);
  GeneratedHeader header;
  header.namespace_name = scene_.name + "_" + model;
  header.file_name = header.namespace_name + ".hpp";

  const int n_parameters = static_cast<int>(system_.jet->parameters().size());
  const int n_coordinates = system_.jet->coordinate_count();
  const int n_multipliers =
      system_.model == ModelKind::suslov ? 0 : static_cast<int>(scene_.constraints.size());
  const int n_hidden = static_cast<int>(system_.hidden_constraints.size());
  const int n_invariants = static_cast<int>(scene_.invariants.size());
  const int n_reference = static_cast<int>(scene_.reference.size());
  const bool dense = options_.jacobian == JacobianKind::dense;
  const bool sparse = options_.jacobian == JacobianKind::sparse;

  // Lower everything into one DAG, in the order the functions are printed, so that a
  // subexpression is one instruction wherever it occurs.
  std::vector<FunctionPlan> plans;
  const std::vector<std::pair<std::string, std::string>> state_inputs = {
      {"double", "t"}, {"const double*", "y"}, {"const double*", "yp"}, {"const double*", "p"}};
  {
    FunctionPlan f;
    f.name = "residual";
    f.doc = "/// F(t, y, y') = 0, IDA form; r has n_states entries.\n";
    f.parameters = state_inputs;
    f.parameters.push_back({"double*", "r"});
    for (int i = 0; i < n; ++i) {
      const std::string comment = static_cast<size_t>(i) < system_.residual_names.size()
                                      ? sanitize_comment(system_.residual_names[static_cast<size_t>(i)])
                                      : "";
      f.assignments.push_back(
          {"r[" + std::to_string(i) + "]", dag_.add(system_.residuals[static_cast<size_t>(i)]),
           comment});
    }
    plans.push_back(std::move(f));
  }
  if (dense || sparse) {
    FunctionPlan f;
    f.parameters = {{"double", "t"},  {"const double*", "y"}, {"const double*", "yp"},
                    {"double", "cj"}, {"const double*", "p"}};
    if (dense) {
      f.name = "jacobian";
      f.doc = "/// J = dF/dy + cj dF/dy', column-major n_states x n_states.\n";
      f.parameters.push_back({"double*", "J"});
      f.prologue = "  for (int k = 0; k < n_states * n_states; ++k) J[k] = 0.0;\n";
      for (int j = 0; j < n; ++j)
        for (int k = jacobian_.colptr[static_cast<size_t>(j)];
             k < jacobian_.colptr[static_cast<size_t>(j) + 1]; ++k) {
          const int i = jacobian_.rowind[static_cast<size_t>(k)];
          const size_t at = static_cast<size_t>(i) + static_cast<size_t>(j) * static_cast<size_t>(n);
          f.assignments.push_back({"J[" + std::to_string(at) + "]", dag_.add(jacobian_.entries[at]),
                                   "(" + std::to_string(i) + ", " + std::to_string(j) + ")"});
        }
    } else {
      f.name = "jacobian_values";
      f.doc = "/// Nonzero values of J = dF/dy + cj dF/dy' in compressed-column order\n"
              "/// (jacobian_colptr, jacobian_rowind).\n";
      f.parameters.push_back({"double*", "values"});
      for (int j = 0; j < n; ++j)
        for (int k = jacobian_.colptr[static_cast<size_t>(j)];
             k < jacobian_.colptr[static_cast<size_t>(j) + 1]; ++k) {
          const int i = jacobian_.rowind[static_cast<size_t>(k)];
          const size_t at = static_cast<size_t>(i) + static_cast<size_t>(j) * static_cast<size_t>(n);
          f.assignments.push_back({"values[" + std::to_string(k) + "]",
                                   dag_.add(jacobian_.entries[at]),
                                   "(" + std::to_string(i) + ", " + std::to_string(j) + ")"});
        }
    }
    plans.push_back(std::move(f));
  }
  if (n_hidden > 0) {
    FunctionPlan g;
    g.name = "hidden_constraints";
    g.doc = "/// Hidden constraints g(t, y) = 0 (derivatives of the equations the index-1 form\n"
            "/// differentiated away); they fix consistent initial values and drift during\n"
            "/// integration.\n";
    g.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"},
                    {"double*", "g"}};
    for (int i = 0; i < n_hidden; ++i)
      g.assignments.push_back(
          {"g[" + std::to_string(i) + "]",
           dag_.add(system_.hidden_constraints[static_cast<size_t>(i)]),
           static_cast<size_t>(i) < system_.hidden_constraint_names.size()
               ? sanitize_comment(system_.hidden_constraint_names[static_cast<size_t>(i)])
               : ""});
    plans.push_back(std::move(g));

    FunctionPlan G;
    G.name = "hidden_constraints_jacobian";
    G.doc = "/// G = dg/dy, column-major n_hidden x n_states.\n";
    G.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"},
                    {"double*", "G"}};
    G.prologue = "  for (int k = 0; k < n_hidden * n_states; ++k) G[k] = 0.0;\n";
    const std::vector<GiNaC::ex> entries = hidden_constraint_jacobian(system_);
    for (size_t at = 0; at < entries.size(); ++at)
      if (!entries[at].is_zero())
        G.assignments.push_back({"G[" + std::to_string(at) + "]", dag_.add(entries[at]),
                                 "(" + std::to_string(at % static_cast<size_t>(n_hidden)) + ", " +
                                     std::to_string(at / static_cast<size_t>(n_hidden)) + ")"});
    plans.push_back(std::move(G));
  }
  if (n_invariants > 0) {
    FunctionPlan f;
    f.name = "invariants";
    f.doc = "/// The scene's invariants I(t, y, y'), in invariant_names order.\n";
    f.parameters = state_inputs;
    f.parameters.push_back({"double*", "out"});
    const std::vector<GiNaC::ex> invariants = invariants_in_states(scene_, system_);
    for (int i = 0; i < n_invariants; ++i)
      f.assignments.push_back({"out[" + std::to_string(i) + "]",
                               dag_.add(invariants[static_cast<size_t>(i)]),
                               sanitize_comment(scene_.invariants[static_cast<size_t>(i)].first)});
    plans.push_back(std::move(f));
  }
  if (n_reference > 0) {
    FunctionPlan f;
    f.name = "reference";
    f.doc = "/// The scene's reference solution q_c(t) for the coordinates reference_coordinate.\n";
    f.parameters = {{"double", "t"}, {"const double*", "p"}, {"double*", "q"}};
    for (int i = 0; i < n_reference; ++i) {
      const auto& [coordinate, expression] = scene_.reference[static_cast<size_t>(i)];
      f.assignments.push_back({"q[" + std::to_string(i) + "]", dag_.add(expression),
                               sanitize_comment(system_.jet->coordinates().at(
                                   static_cast<size_t>(coordinate)))});
    }
    plans.push_back(std::move(f));
  }

  // Singular-set monitors (runtime additions): quantities whose zeros make the residual or
  // the hidden constraints non-smooth; the runtime watches them as root functions.
  const std::vector<SingularQuantity> singular = singular_quantities(system_);
  const int n_singular = static_cast<int>(singular.size());
  if (n_singular > 0) {
    FunctionPlan f;
    f.name = "singular_quantities";
    f.doc = "/// Quantities that vanish where the equations are singular (bases of square roots,\n"
            "/// of negative powers and arguments of logarithms), in singular_names order.\n";
    f.parameters = {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"},
                    {"double*", "s"}};
    for (int i = 0; i < n_singular; ++i)
      f.assignments.push_back({"s[" + std::to_string(i) + "]",
                               dag_.add(singular[static_cast<size_t>(i)].expression), ""});
    plans.push_back(std::move(f));
  }

  // ---- Sensitivity additions (docs/generated-code.md): dF/dp and dg/dp, column-major, only
  // when asked for (HeaderOptions::sensitivities) and the scene has parameters.
  if (options_.sensitivities && n_parameters > 0) {
    const ParameterJacobian pj = parameter_jacobian(system_);
    auto matrix_plan = [&](const std::string& name, const std::string& doc, const std::string& out,
                           int rows, const std::vector<GiNaC::ex>& entries, const std::vector<int>& nonzeros,
                           std::vector<std::pair<std::string, std::string>> parameters) {
      FunctionPlan f;
      f.name = name;
      f.doc = doc;
      f.parameters = std::move(parameters);
      f.parameters.push_back({"double*", out});
      f.prologue = "  for (int k = 0; k < " + std::to_string(rows * n_parameters) + "; ++k) " + out + "[k] = 0.0;\n";
      for (int at : nonzeros)
        f.assignments.push_back({out + "[" + std::to_string(at) + "]", dag_.add(entries[static_cast<size_t>(at)]),
                                 "(" + std::to_string(at % rows) + ", " + std::to_string(at / rows) + ")"});
      plans.push_back(std::move(f));
    };
    matrix_plan("residual_parameter_jacobian", "/// dF/dp, column-major n_states x n_parameters.\n", "Fp", n,
                pj.residual, pj.residual_nonzeros, state_inputs);
    if (n_hidden > 0)
      matrix_plan("hidden_parameter_jacobian", "/// dg/dp of the hidden constraints, column-major n_hidden x n_parameters.\n",
                  "Gp", n_hidden, pj.hidden, pj.hidden_nonzeros,
                  {{"double", "t"}, {"const double*", "y"}, {"const double*", "p"}});
  }
  // ---- end of the sensitivity additions.

  // Function bodies (this also counts operations).
  std::vector<std::string> bodies;
  for (FunctionPlan& plan : plans) {
    std::set<std::string> allowed;
    for (const auto& parameter : plan.parameters) allowed.insert(parameter.second);
    bodies.push_back(function_text(plan, allowed));
    header.before_cse += plan.before;
    header.after_cse += plan.after;
  }

  std::ostringstream out;
  const std::string scene_file =
      scene_.source_path.empty() ? std::string("a scene built in code") : base_name(scene_.source_path);

  // Banner. Everything taken from the scene is sanitised: it lives in `//` comments only.
  out << "// " << sanitize_comment(header.file_name) << ": generated by nhc " << NHC_VERSION
      << " from " << sanitize_comment(scene_file) << ", model " << model << ".\n"
      << "// Do not edit: regenerate with\n"
      << "//   nhc generate " << sanitize_comment(scene_file) << " --model " << model
      << " --jacobian " << to_string(options_.jacobian) << (options_.sensitivities ? " --sensitivities" : "") << "\n"
      << "// Layout: docs/generated-code.md.\n"
      << "//\n"
      << "// Scene " << sanitize_comment(scene_.name) << ": coordinates "
      << sanitize_comment(joined(system_.jet->coordinates(), ", "));
  if (n_parameters > 0)
    out << "; parameters " << sanitize_comment(joined(system_.jet->parameters(), ", "));
  out << "\n//   L = " << sanitize_comment(scene_notation(scene_.lagrangian, *scene_.jet)) << "\n";
  for (size_t a = 0; a < scene_.constraints.size(); ++a)
    out << "//   f" << a + 1 << " = "
        << sanitize_comment(scene_notation(scene_.constraints[a], *scene_.jet)) << "\n";
  out << "// Index-1 form: " << n << " states, " << n_hidden << " hidden constraint"
      << (n_hidden == 1 ? "" : "s") << ".\n"
      << "//\n"
      << "// Floating-point operations (+, -, *, /, calls) without and with common-subexpression\n"
      << "// elimination:\n";
  for (const FunctionPlan& plan : plans) out << describe_count(plan.name, plan.before, plan.after);
  out << describe_count("total", header.before_cse, header.after_cse);
  out << "\n#pragma once\n\n#include <cmath>\n";
  out << kModelTableDeclaration;
  out << "\nnamespace nhc_gen::" << header.namespace_name << " {\n\n";

  // Metadata.
  auto strings = [](const std::vector<std::string>& v) {
    return list_of(v, [](const std::string& s) { return cpp_string_literal(s); });
  };
  auto ints = [](const std::vector<int>& v) {
    return list_of(v, [](int k) { return std::to_string(k); });
  };
  auto doubles = [](const std::vector<double>& v) {
    return list_of(v, [](double x) { return cpp_double_literal(x); });
  };
  std::vector<std::string> state_names;
  std::vector<int> state_variable, state_order;
  std::vector<double> differential_id;
  for (const StateComponent& s : system_.states) {
    state_names.push_back(s.name);
    state_variable.push_back(s.kind == VariableKind::coordinate ? s.index : n_coordinates + s.index);
    state_order.push_back(s.order);
    differential_id.push_back(s.differential ? 1.0 : 0.0);
  }
  std::vector<std::string> residual_names = system_.residual_names;
  residual_names.resize(static_cast<size_t>(n));
  out << "inline constexpr int n_states = " << n << ";\n"
      << "inline constexpr int n_parameters = " << n_parameters << ";\n"
      << "inline constexpr int n_coordinates = " << n_coordinates << ";\n"
      << "inline constexpr int n_multipliers = " << n_multipliers << ";\n"
      << "inline constexpr int n_hidden = " << n_hidden << ";\n"
      << "inline constexpr int n_invariants = " << n_invariants << ";\n"
      << "inline constexpr int n_reference = " << n_reference << ";\n"
      << "inline constexpr int n_singular = " << n_singular << ";\n"
      << "inline constexpr const char* model_name = " << cpp_string_literal(model) << ";\n"
      << "inline constexpr const char* scene_name = " << cpp_string_literal(scene_.name) << ";\n\n"
      << "/// y[k] holds the state_order[k]-th derivative of variable state_variable[k]\n"
      << "/// (0..n_coordinates-1: coordinates, then multipliers).\n"
      << "inline constexpr const char* state_names[n_states] = " << strings(state_names) << ";\n"
      << "inline constexpr int state_variable[n_states] = " << ints(state_variable) << ";\n"
      << "inline constexpr int state_order[n_states] = " << ints(state_order) << ";\n"
      << "/// IDA id: 1.0 differential, 0.0 algebraic.\n"
      << "inline constexpr double differential_id[n_states] = " << doubles(differential_id)
      << ";\n"
      << "inline constexpr const char* residual_names[n_states] = " << strings(residual_names)
      << ";\n";
  if (n_parameters > 0) {
    out << "inline constexpr const char* parameter_names[n_parameters] = "
        << strings(system_.jet->parameters()) << ";\n"
        << "inline constexpr double default_parameters[n_parameters] = "
        << doubles(scene_.parameter_values) << ";\n";
  } else {
    out << "/// No parameters; C++ has no empty arrays, so one unused placeholder each.\n"
        << "inline constexpr const char* parameter_names[1] = {nullptr};\n"
        << "inline constexpr double default_parameters[1] = {0.0};\n";
  }
  if (n_hidden > 0) {
    std::vector<std::string> names = system_.hidden_constraint_names;
    names.resize(static_cast<size_t>(n_hidden));
    out << "inline constexpr const char* hidden_names[n_hidden] = " << strings(names) << ";\n";
  }
  if (n_invariants > 0) {
    std::vector<std::string> names;
    for (const auto& inv : scene_.invariants) names.push_back(inv.first);
    out << "inline constexpr const char* invariant_names[n_invariants] = " << strings(names)
        << ";\n";
  }
  if (n_reference > 0) {
    std::vector<int> coordinates;
    for (const auto& r : scene_.reference) coordinates.push_back(r.first);
    out << "inline constexpr int reference_coordinate[n_reference] = " << ints(coordinates)
        << ";\n";
  }
  if (n_singular > 0) {
    std::vector<std::string> names;
    for (const auto& q : singular) names.push_back(q.name);
    out << "inline constexpr const char* singular_names[n_singular] = " << strings(names)
        << ";\n";
  }
  if (sparse) {
    out << "\n/// Compressed-column structure of J (the entries not identically zero).\n"
        << "inline constexpr int jacobian_nnz = " << jacobian_.rowind.size() << ";\n"
        << "inline constexpr int jacobian_colptr[n_states + 1] = " << ints(jacobian_.colptr)
        << ";\n";
    if (jacobian_.rowind.empty())
      out << "inline constexpr int jacobian_rowind[1] = {0};  // no nonzeros: placeholder\n";
    else
      out << "inline constexpr int jacobian_rowind[jacobian_nnz] = " << ints(jacobian_.rowind)
          << ";\n";
  }

  for (const std::string& body : bodies) out << "\n" << body;

  // The table (docs/generated-code.md): every pointer null for what the scene does not need.
  auto has = [&](const std::string& function) {
    return std::any_of(plans.begin(), plans.end(),
                       [&](const FunctionPlan& p) { return p.name == function; });
  };
  auto pointer = [&](const std::string& function) {
    return has(function) ? "&" + function : std::string("nullptr");
  };
  auto field = [&](bool present, const std::string& name, const char* absent = "nullptr") {
    return present ? name : std::string(absent);
  };
  const std::vector<std::string> fields = {
      std::to_string(kModelTableAbiVersion),
      "scene_name",
      "model_name",
      "n_states",
      "n_parameters",
      "n_coordinates",
      "n_multipliers",
      "n_hidden",
      "n_invariants",
      "n_reference",
      "state_names",
      "state_variable",
      "state_order",
      "differential_id",
      field(n_parameters > 0, "parameter_names"),
      field(n_parameters > 0, "default_parameters"),
      field(n_hidden > 0, "hidden_names"),
      field(n_invariants > 0, "invariant_names"),
      field(n_reference > 0, "reference_coordinate"),
      pointer("residual"),
      pointer("jacobian"),
      field(sparse, "jacobian_nnz", "0"),
      field(sparse, "jacobian_colptr"),
      field(sparse, "jacobian_rowind"),
      pointer("jacobian_values"),
      pointer("hidden_constraints"),
      pointer("hidden_constraints_jacobian"),
      pointer("invariants"),
      pointer("reference"),
      "residual_names",
      "n_singular",
      field(n_singular > 0, "singular_names"),
      pointer("singular_quantities"),
      pointer("residual_parameter_jacobian"),  // abi_version >= 3: sensitivity additions
      pointer("hidden_parameter_jacobian"),
  };
  out << "\n/// Everything above as the C table of docs/generated-code.md.\n"
      << "inline const nhc_model_table* model_table() noexcept {\n"
      << "  static const nhc_model_table table = {\n";
  for (const std::string& f : fields) out << "      " << f << ",\n";
  out << "  };\n"
      << "  return &table;\n"
      << "}\n";
  out << "\n}  // namespace nhc_gen::" << header.namespace_name << "\n"
      << "\n#ifdef NHC_EXPORT_MODEL_TABLE\n"
      << "extern \"C\" const nhc_model_table* nhc_model_table_get(void) {\n"
      << "  return nhc_gen::" << header.namespace_name << "::model_table();\n"
      << "}\n"
      << "#endif  // NHC_EXPORT_MODEL_TABLE\n";

  header.text = out.str();
  return header;
}

}  // namespace

GeneratedHeader generate_header(const Scene& scene, const Index1System& system,
                                const HeaderOptions& options) {
  if (!system.jet) throw MathError("index-1 system without a jet space");
  // The scene name becomes a namespace and a file name: only a validated identifier may. (Scenes
  // built in code skip the loader's checks; every other name only enters comments and literals.)
  if (!is_valid_identifier(scene.name))
    throw InputError({scene.source_path.empty() ? "scene" : scene.source_path, 0, 0},
                     "invalid scene name '" + sanitize_comment(scene.name) +
                         "': it must be a C++ identifier");
  const size_t n = system.states.size();
  if (system.residuals.size() != n || system.y.size() != n || system.yp.size() != n)
    throw MathError("inconsistent index-1 system: " + std::to_string(n) + " states, " +
                    std::to_string(system.residuals.size()) + " residuals");
  return HeaderWriter(scene, system, options).write();
}

}  // namespace nhc
