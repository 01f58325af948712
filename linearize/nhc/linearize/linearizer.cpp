#include "nhc/linearize/linearizer.hpp"

#include "nhc/base/primed_name.hpp"
#include "nhc/base/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "nhc/analysis/consistent_initialization.hpp"
#include "nhc/analysis/dae_system.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/linearize/cyclic_reduction.hpp"
#include "nhc/linearize/manifold_linearization.hpp"
#include "nhc/expr/numeric_program.hpp"
#include "nhc/linearize/spectrum.hpp"
#include "nhc/linearize/steady_families.hpp"

namespace nhc {

namespace {

std::string number(double v) { return base::number_text(v, 6); }

/// The state of the reduced system at one point: z, z' of the differential states, and the
/// parameters and t as a GiNaC substitution.
struct NumericPoint {
  GiNaC::exmap base;              ///< t, parameters and inputs
  std::vector<double> constants;  ///< the same values: t, the parameters, the inputs in JetSpace order
  Eigen::VectorXd z;
  Eigen::VectorXd zp;  ///< per state; 0 for algebraic ones
};

/// The inputs of the numeric programs: t, the parameters, the scene's inputs, then z and z' of
/// the reduced states.
std::vector<GiNaC::ex> program_inputs(const Scene& scene, const CyclicReduction& r) {
  std::vector<GiNaC::ex> inputs{scene.jet->time()};
  for (int q = 0; q < static_cast<int>(scene.parameter_values.size()); ++q) inputs.push_back(scene.jet->parameter(q));
  for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k) inputs.push_back(scene.jet->input(k));
  for (const ReducedComponent& z : r.components) inputs.push_back(z.value);
  for (const ReducedComponent& z : r.components)
    if (z.differential) inputs.push_back(z.derivative);
  return inputs;
}

std::vector<double> program_values(const CyclicReduction& r, const NumericPoint& p) {
  std::vector<double> values = p.constants;
  for (Eigen::Index c = 0; c < p.z.size(); ++c) values.push_back(p.z(c));
  for (std::size_t c = 0; c < r.components.size(); ++c)
    if (r.components[c].differential) values.push_back(p.zp(static_cast<Eigen::Index>(c)));
  return values;
}

/// A matrix of expressions as entries of a numeric program (structural zeros skipped).
struct MatrixOutputs {
  Eigen::Index rows = 0, cols = 0;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> entries;  ///< per output, in order
  int first = 0;                                               ///< index of the first output
};

MatrixOutputs add_matrix(NumericProgram& program, const std::vector<std::vector<GiNaC::ex>>& m, std::size_t cols) {
  MatrixOutputs out;
  out.rows = static_cast<Eigen::Index>(m.size());
  out.cols = static_cast<Eigen::Index>(cols);
  out.first = -1;
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = 0; j < m[i].size(); ++j) {
      if (m[i][j].is_zero()) continue;
      const int k = program.add(m[i][j]);
      if (out.first < 0) out.first = k;
      out.entries.emplace_back(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
  return out;
}

Eigen::MatrixXd matrix_of(const MatrixOutputs& m, const std::vector<double>& values) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(m.rows, m.cols);
  for (std::size_t k = 0; k < m.entries.size(); ++k)
    out(m.entries[k].first, m.entries[k].second) = values[static_cast<std::size_t>(m.first) + k];
  return out;
}

/// The linearization over `wanted` in that order (LinearizeOptions::states): the rows and columns
/// of A, the rows of B, the columns of C and the family directions permuted. InputError at
/// "--states" when `wanted` is not the whole reduced state.
void order_states(Linearization& lin, const std::vector<std::string>& wanted) {
  std::vector<std::string> sorted_wanted = wanted, sorted_states = lin.states;
  std::sort(sorted_wanted.begin(), sorted_wanted.end());
  std::sort(sorted_states.begin(), sorted_states.end());
  if (sorted_wanted != sorted_states) {
    std::vector<std::string> missing;
    for (const std::string& s : lin.states)
      if (std::find(wanted.begin(), wanted.end(), s) == wanted.end()) missing.push_back(s);
    throw InputError({"--states", 0, 0},
                     "--states names " + std::to_string(wanted.size()) + " states; the linearization has " +
                         std::to_string(lin.states.size()) + " (" + join_names(lin.states) + ")" +
                         (missing.empty() ? std::string() : ": add " + join_names(missing)) +
                         (lin.eliminated.empty() ? std::string()
                                                 : "; the hidden constraints eliminate " + join_names(lin.eliminated)));
  }
  const auto n = static_cast<Eigen::Index>(wanted.size());
  Eigen::PermutationMatrix<Eigen::Dynamic> P(n);  // P δs_old = δs_new
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto old =
        std::find(lin.states.begin(), lin.states.end(), wanted[static_cast<std::size_t>(k)]) - lin.states.begin();
    P.indices()(old) = static_cast<int>(k);
  }
  lin.A = P * lin.A * P.transpose();
  lin.B = P * lin.B;
  lin.C = lin.C * P.transpose();
  for (SteadyFamily& f : lin.families) {
    const Eigen::VectorXd v = P * Eigen::Map<const Eigen::VectorXd>(f.direction.data(), n);
    f.direction.assign(v.data(), v.data() + n);
  }
  lin.states = wanted;
}

/// ∂f/∂u_k for each residual f (rows) and each of the scene's inputs (columns).
std::vector<std::vector<GiNaC::ex>> input_derivatives(const std::vector<GiNaC::ex>& residuals, const Scene& scene) {
  const JetSpace& jet = *scene.jet;
  std::vector<std::vector<GiNaC::ex>> entries;
  for (const GiNaC::ex& f : residuals) {
    std::vector<GiNaC::ex> row;
    for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k)
      row.push_back(depends_on(f, jet.input(k)) ? f.diff(jet.input(k)) : GiNaC::ex(0));
    entries.push_back(std::move(row));
  }
  return entries;
}

}  // namespace

struct Linearizer::Impl {
  Scene scene;
  ModelKind model;
  LinearizeOptions options;
  StructuralAnalysis analysis;
  Index1System system;
  CyclicReduction reduced;
  /// The residual and hidden constraints (outputs: g, then F), and dF/dz, dF/dz', dg/dz.
  std::optional<NumericProgram> functions, jacobians;
  MatrixOutputs dF_dz, dF_dzp, dg_dz, dF_du;
  /// The scene's outputs in reduced states: names, dh/dz, dh/dz', dh/du; and the notes on those
  /// left out.
  std::vector<std::string> output_names, output_notes;
  MatrixOutputs dh_dz, dh_dzp, dh_du;
  void compile_outputs();
  /// Why at() refuses (the equations contain t), or empty.
  std::string time_dependence;
  /// Per reduced component: the index-1 state its value is (k, from y' when true), and the state
  /// whose y' its derivative is (-1 for algebraic ones), for along().
  std::vector<std::pair<int, bool>> value_source;
  std::vector<int> derivative_source;
  /// ∂F/∂u of the full index-1 residual over (t, p, u, y, y'), for input_jacobian().
  std::optional<NumericProgram> full_input_jacobian;
  MatrixOutputs dF_full_du;
  ManifoldInput manifold_input(const NumericPoint& p) const;
  /// LinearizeOptions::turn: per reduced component, the generator X of the turn: 1 on the angle
  /// (turn_angle), −y^(k) on x^(k) and x^(k) on y^(k) (turn_partner, turn_sign); 0 elsewhere.
  int turn_angle = -1;
  std::vector<int> turn_partner;
  std::vector<double> turn_sign;
  bool turning() const { return turn_angle >= 0; }
  /// X(z) over the reduced components.
  Eigen::VectorXd generator(const Eigen::VectorXd& z) const;
  /// The point turned by c (the angle + c, each (x^(k), y^(k)) rotated, in z and z').
  NumericPoint turned(const NumericPoint& p, double c) const;
  void check_invariant(const NumericPoint& p) const;
  void setup_turn(const LinearizeOptions::Turn& turn);

  void compile_programs();
  /// g and F at the point.
  std::pair<Eigen::VectorXd, Eigen::VectorXd> hidden_and_residual(const NumericPoint& p) const;

  NumericPoint operating_point(const Scene& at_scene, Linearization& out) const;
  void check_stationary(const NumericPoint& p, Linearization& out) const;
  std::optional<Eigen::VectorXd> velocity(const NumericPoint& p, const ManifoldLinearization& lin,
                                          const Eigen::MatrixXd& G_dependent, const Eigen::VectorXd& s) const;
  std::vector<SteadyFamily> families_at(const NumericPoint& p, const ManifoldLinearization& lin,
                                        const std::vector<std::string>& states, int zero_eigenvalues) const;
  std::string describe_basis(const ManifoldLinearization& lin) const;
  /// out's states, eliminated and algebraic components and basis, by name, from lin's positions.
  void name_states(const ManifoldLinearization& lin, Linearization& out) const;
  /// (t, the scene's parameters, u) for a point (y, y') of the index-1 system, whose sizes are
  /// checked (InputError naming y, yp or u).
  std::vector<double> point_constants(double t, const std::vector<double>& y, const std::vector<double>& yp,
                                      const std::vector<double>& u) const;
};

NumericPoint Linearizer::Impl::operating_point(const Scene& s, Linearization& out) const {
  const ConsistentPoint cp = consistent_initial_point(s, analysis);
  if (!cp.leading_solved)
    throw MathError("the system Jacobian of the " + to_string(model) +
                    " model is singular at the operating point: the leading derivatives cannot be solved there");
  for (const std::string& note : cp.notes) out.notes.push_back(note);
  std::vector<double> y0, yp0;
  initial_state(system, cp, y0, yp0);

  NumericPoint p;
  p.base = s.parameter_substitution();
  p.base[s.jet->time()] = s.initial.t0;
  p.constants.push_back(s.initial.t0);
  p.constants.insert(p.constants.end(), s.parameter_values.begin(), s.parameter_values.end());
  const GiNaC::exmap inputs = s.input_substitution(s.initial.t0);
  for (int k = 0; k < static_cast<int>(s.inputs.size()); ++k) {
    const GiNaC::ex& u = s.jet->input(k);
    p.base[u] = inputs.at(u);
    p.constants.push_back(GiNaC::ex_to<GiNaC::numeric>(inputs.at(u)).to_double());
  }
  GiNaC::exmap full = p.base;
  for (int k = 0; k < system.size(); ++k) {
    full[system.y[static_cast<std::size_t>(k)]] = y0[static_cast<std::size_t>(k)];
    full[system.yp[static_cast<std::size_t>(k)]] = yp0[static_cast<std::size_t>(k)];
  }
  const auto n = static_cast<Eigen::Index>(reduced.components.size());
  p.z = Eigen::VectorXd::Zero(n);
  p.zp = Eigen::VectorXd::Zero(n);
  for (Eigen::Index c = 0; c < n; ++c) {
    const ReducedComponent& z = reduced.components[static_cast<std::size_t>(c)];
    p.z(c) = evaluate_real(z.value, full, z.name);
    if (z.differential) p.zp(c) = evaluate_real(z.derivative, full, "the derivative of " + z.name);
  }
  for (int q = 0; q < static_cast<int>(s.parameter_values.size()); ++q)
    out.point.emplace_back(s.jet->parameters()[static_cast<std::size_t>(q)],
                           s.parameter_values[static_cast<std::size_t>(q)]);
  for (int k = 0; k < system.size(); ++k)
    out.point.emplace_back(system.states[static_cast<std::size_t>(k)].name, y0[static_cast<std::size_t>(k)]);
  return p;
}

void Linearizer::Impl::check_stationary(const NumericPoint& p, Linearization& out) const {
  const double scale = 1.0 + (p.z.size() ? p.z.cwiseAbs().maxCoeff() : 0.0);
  double worst = 0.0;
  // About a relative equilibrium: stationary in the turning frame, z' = ω X(z).
  const Eigen::VectorXd drift = out.turn_rate * generator(p.z);
  for (std::size_t c = 0; c < reduced.components.size(); ++c) {
    const double rate = std::abs(p.zp(static_cast<Eigen::Index>(c)) - drift(static_cast<Eigen::Index>(c))) / scale;
    const ReducedComponent& z = reduced.components[c];
    // A kept cyclic coordinate may drift: the equations do not contain it (LinearizeOptions::keep).
    const bool drifts =
        z.order == 0 && std::find(reduced.kept.begin(), reduced.kept.end(), z.name) != reduced.kept.end();
    if (z.differential && !drifts && rate >= worst && (rate > worst || out.worst_state.empty())) {
      worst = rate;
      out.worst_state = reduced.components[c].name;
    }
  }
  out.defect = worst;
  if (worst > options.stationarity) {
    std::size_t c = 0;
    while (reduced.components[c].name != out.worst_state) ++c;
    const ReducedComponent& z = reduced.components[c];
    const std::string moving = "the operating point is not stationary" +
                               std::string(turning() ? " in the turning frame" : "") + ": d/dt " + out.worst_state +
                               " = " + number(p.zp(static_cast<Eigen::Index>(c))) + " (defect " + number(worst) +
                               " > " + number(options.stationarity) + ", relative to 1 + max |state|)";
    if (z.order > 0 || z.multiplier || turning())
      throw MathError(moving + "; choose [initial] or --at values of an equilibrium or steady motion");
    // A coordinate that moves at the point but is not cyclic: a steady turn or spin (a relative
    // equilibrium) whose symmetry moves this coordinate together with others (docs/linearize.md,
    // "Relative equilibria").
    std::string depends;
    for (std::size_t i = 0; i < reduced.residuals.size(); ++i)
      if (depends_on(reduced.residuals[i], z.value))
        depends += (depends.empty() ? "" : ", ") + reduced.residual_names[i];
    for (std::size_t i = 0; i < reduced.hidden.size(); ++i)
      if (depends_on(reduced.hidden[i], z.value)) depends += (depends.empty() ? "" : ", ") + reduced.hidden_names[i];
    throw MathError(moving + ": " + z.name + " moves but is not cyclic (" +
                    (depends.empty() ? std::string("the equations contain it") : "it appears in " + depends) +
                    "), so this steady motion is not an equilibrium of the system reduced by its cyclic coordinates; "
                    "if it is a relative equilibrium (a steady turn or spin, " +
                    z.name +
                    " moving together with other coordinates), write the scene in coordinates where that symmetry is "
                    "cyclic (docs/linearize.md, \"Relative equilibria\"), or choose a point with " +
                    z.name + "' = 0");
  }
}

/// z'_D on the constraint manifold at the reduced state s: the dependent states solved from
/// g = 0 and (z'_D, z_A) from F = 0 by chord iterations with the point's matrices.
std::optional<Eigen::VectorXd> Linearizer::Impl::velocity(const NumericPoint& p, const ManifoldLinearization& lin,
                                                          const Eigen::MatrixXd& G_dependent,
                                                          const Eigen::VectorXd& s) const {
  NumericPoint q = p;
  for (std::size_t i = 0; i < lin.independent.size(); ++i)
    q.z(lin.differential[static_cast<std::size_t>(lin.independent[i])]) = s(static_cast<Eigen::Index>(i));
  const auto nD = static_cast<Eigen::Index>(lin.differential.size());
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> solver;  // Eigen's QR of an empty matrix crashes
  if (G_dependent.size() > 0) solver.compute(G_dependent);
  for (int iteration = 0; iteration < 60; ++iteration) {
    double step = 0.0;
    if (!reduced.hidden.empty() && !lin.dependent.empty()) {
      const Eigen::VectorXd g = hidden_and_residual(q).first;
      const Eigen::VectorXd d = -solver.solve(g);
      for (std::size_t r = 0; r < lin.dependent.size(); ++r)
        q.z(lin.differential[static_cast<std::size_t>(lin.dependent[r])]) += d(static_cast<Eigen::Index>(r));
      step += d.norm();
    }
    const Eigen::VectorXd F = hidden_and_residual(q).second;
    const Eigen::VectorXd u = -lin.K.solve(F);
    for (Eigen::Index k = 0; k < nD; ++k) q.zp(lin.differential[static_cast<std::size_t>(k)]) += u(k);
    for (std::size_t k = 0; k < lin.algebraic.size(); ++k)
      q.z(lin.algebraic[k]) += u(nD + static_cast<Eigen::Index>(k));
    step += u.norm();
    if (!std::isfinite(step)) return std::nullopt;
    if (step <= 1e-14 * (1.0 + q.z.norm() + q.zp.norm())) {
      Eigen::VectorXd out(static_cast<Eigen::Index>(lin.independent.size()));
      for (std::size_t i = 0; i < lin.independent.size(); ++i)
        out(static_cast<Eigen::Index>(i)) = q.zp(lin.differential[static_cast<std::size_t>(lin.independent[i])]);
      return out;
    }
  }
  return std::nullopt;
}

/// The reduced velocity h(s) and s* for steady_families().
std::vector<SteadyFamily> Linearizer::Impl::families_at(const NumericPoint& p, const ManifoldLinearization& lin,
                                                        const std::vector<std::string>& states,
                                                        int zero_eigenvalues) const {
  Eigen::VectorXd s_star(static_cast<Eigen::Index>(lin.independent.size()));
  for (std::size_t i = 0; i < lin.independent.size(); ++i)
    s_star(static_cast<Eigen::Index>(i)) = p.z(lin.differential[static_cast<std::size_t>(lin.independent[i])]);
  Eigen::MatrixXd G_dependent(static_cast<Eigen::Index>(reduced.hidden.size()),
                              static_cast<Eigen::Index>(lin.dependent.size()));
  if (G_dependent.size()) {
    const Eigen::MatrixXd G = matrix_of(dg_dz, jacobians->evaluate(program_values(reduced, p), "the Jacobians"));
    for (std::size_t r = 0; r < lin.dependent.size(); ++r)
      G_dependent.col(static_cast<Eigen::Index>(r)) =
          G.col(lin.differential[static_cast<std::size_t>(lin.dependent[r])]);
  }
  const ReducedVelocity h = [&](const Eigen::VectorXd& s) { return velocity(p, lin, G_dependent, s); };
  return steady_families(lin.A, s_star, h, zero_eigenvalues, states, options.zero_tolerance);
}

void Linearizer::Impl::name_states(const ManifoldLinearization& lin, Linearization& out) const {
  auto name = [&](int component) { return reduced.components[static_cast<std::size_t>(component)].name; };
  for (int k : lin.independent) out.states.push_back(name(lin.differential[static_cast<std::size_t>(k)]));
  for (int k : lin.dependent) out.eliminated.push_back(name(lin.differential[static_cast<std::size_t>(k)]));
  for (int k : lin.algebraic) out.algebraic.push_back(name(k));
  out.basis = describe_basis(lin);
}

std::string Linearizer::Impl::describe_basis(const ManifoldLinearization& lin) const {
  auto names = [&](const std::vector<int>& positions, bool through_differential) {
    std::vector<std::string> out;
    for (int k : positions)
      out.push_back(reduced
                        .components[static_cast<std::size_t>(
                            through_differential ? lin.differential[static_cast<std::size_t>(k)] : k)]
                        .name);
    return out;
  };
  std::ostringstream text;
  text << "states: the differential states of the index-1 system";
  if (!lin.algebraic.empty())
    text << "; the algebraic " << join_names(names(lin.algebraic, false)) << " solved from the residual";
  if (!lin.dependent.empty())
    text << "; " << join_names(names(lin.dependent, true)) << " eliminated by the hidden constraint"
         << (reduced.hidden.size() > 1 ? "s " : " ") << join_names(reduced.hidden_names)
         << " (one state per independent constraint, chosen greedily: coordinates before multipliers, "
            "higher derivatives before lower, larger constraint-gradient column first, each kept if it "
            "raises the rank)";
  else if (!reduced.hidden.empty()) text << "; the hidden constraints cut no direction at this point";
  return text.str();
}

Linearizer::Linearizer(const Scene& scene, ModelKind model, LinearizeOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.scene = scene;
  m.model = model;
  m.options = options;
  const DerivedModel derived = derive_model(scene, model);
  if (!derived.applicable) throw MathError("the " + to_string(model) + " model is not applicable: " + derived.reason);
  m.analysis = analyze_structure(dae_system_of(scene, derived));
  m.analysis.require_nonsingular();
  m.system = reduce_to_index1(m.analysis);
  for (const std::string& name : options.keep) {
    const std::vector<std::string>& coordinates = scene.jet->coordinates();
    if (std::find(coordinates.begin(), coordinates.end(), name) == coordinates.end())
      throw InputError({"--keep", 0, 0}, "--keep " + name + ": not a coordinate of scene " + scene.name +
                                             " (its coordinates: " + join_names(coordinates) + ")");
  }
  m.reduced = reduce_cyclic(m.system, scene.jet->time(), options.keep, false);
  try {
    require_autonomous(m.system, scene.jet->time());
  } catch (const MathError& e) {
    m.time_dependence = e.what();  // at() refuses; along() takes it
  }
  for (const ReducedComponent& z : m.reduced.components) {
    std::pair<int, bool> value{-1, false};
    int derivative = -1;
    for (int k = 0; k < m.system.size(); ++k) {
      if (z.value.is_equal(m.system.y[static_cast<std::size_t>(k)])) value = {k, false};
      if (z.value.is_equal(m.system.yp[static_cast<std::size_t>(k)])) value = {k, true};
      if (z.differential && z.derivative.is_equal(m.system.yp[static_cast<std::size_t>(k)])) derivative = k;
    }
    m.value_source.push_back(value);
    m.derivative_source.push_back(derivative);
  }
  if (!options.turn.angle.empty()) m.setup_turn(options.turn);
  std::vector<std::string> differential;
  for (const ReducedComponent& z : m.reduced.components)
    if (z.differential) differential.push_back(z.name);
  for (const std::string& name : options.states) {
    if (std::count(options.states.begin(), options.states.end(), name) > 1)
      throw InputError({"--states", 0, 0}, "--states names " + name + " twice");
    if (std::find(differential.begin(), differential.end(), name) != differential.end()) continue;
    const bool removed = std::find(m.reduced.cyclic.begin(), m.reduced.cyclic.end(), name) != m.reduced.cyclic.end();
    throw InputError({"--states", 0, 0},
                     "--states " + name + ": not a differential state of the reduced " + to_string(model) + " system" +
                         (removed ? " (" + name + " is cyclic and removed: keep it with --keep " + name + ")" : "") +
                         "; its differential states: " + join_names(differential));
  }
  m.compile_programs();
}

void Linearizer::Impl::compile_programs() {
  const std::vector<GiNaC::ex> inputs = program_inputs(scene, reduced);
  functions.emplace(inputs);
  for (const GiNaC::ex& g : reduced.hidden) functions->add(g);
  for (const GiNaC::ex& f : reduced.residuals) functions->add(f);
  jacobians.emplace(inputs);
  const std::size_t n = reduced.components.size();
  dF_dz = add_matrix(*jacobians, reduced.dF_dz, n);
  dF_dzp = add_matrix(*jacobians, reduced.dF_dzp, n);
  dg_dz = add_matrix(*jacobians, reduced.dg_dz, n);
  // dF/du over the scene's inputs. An input in a hidden constraint would move the constraint
  // manifold with u, which the elimination by Ĝ does not follow: refused.
  const JetSpace& jet = *scene.jet;
  for (std::size_t h = 0; h < reduced.hidden.size(); ++h)
    for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k)
      if (depends_on(reduced.hidden[h], jet.input(k)))
        throw MathError("input '" + scene.inputs[static_cast<std::size_t>(k)].name + "' enters the hidden constraint " +
                        reduced.hidden_names[h] + " of the " + to_string(model) +
                        " model: linearizing with an input that moves the constraint manifold is not supported");
  dF_du = add_matrix(*jacobians, input_derivatives(reduced.residuals, scene), scene.inputs.size());
  compile_outputs();
  std::vector<GiNaC::ex> full_inputs{scene.jet->time()};
  for (int q = 0; q < static_cast<int>(scene.parameter_values.size()); ++q)
    full_inputs.push_back(scene.jet->parameter(q));
  for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k) full_inputs.push_back(scene.jet->input(k));
  full_inputs.insert(full_inputs.end(), system.y.begin(), system.y.end());
  full_inputs.insert(full_inputs.end(), system.yp.begin(), system.yp.end());
  full_input_jacobian.emplace(full_inputs);
  dF_full_du = add_matrix(*full_input_jacobian, input_derivatives(system.residuals, scene), scene.inputs.size());
}

void Linearizer::Impl::compile_outputs() {
  // The symbols the reduced system knows: its states, their derivatives, t, parameters, inputs.
  std::set<GiNaC::ex, GiNaC::ex_is_less> known{scene.jet->time()};
  for (int q = 0; q < static_cast<int>(scene.parameter_values.size()); ++q) known.insert(scene.jet->parameter(q));
  for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k) known.insert(scene.jet->input(k));
  for (const ReducedComponent& z : reduced.components) {
    known.insert(z.value);
    if (z.differential) known.insert(z.derivative);
  }
  std::vector<std::vector<GiNaC::ex>> h_z, h_zp, h_u;
  for (const SceneQuantity& output : scene.outputs) {
    const GiNaC::ex h = system.in_states(output.expression);
    const auto symbols = symbols_through(h);
    const auto unknown =
        std::find_if(symbols.begin(), symbols.end(), [&](const GiNaC::ex& s) { return !known.count(s); });
    if (unknown != symbols.end()) {
      std::ostringstream symbol;
      symbol << *unknown;
      output_notes.push_back("output " + output.name + " is left out of C and D: it uses " + symbol.str() +
                             ", which the reduced " + to_string(model) +
                             " system does not hold (a cyclic coordinate, or a derivative the model does not compute)");
      continue;
    }
    output_names.push_back(output.name);
    std::vector<GiNaC::ex> row_z, row_zp, row_u;
    for (const ReducedComponent& z : reduced.components) {
      row_z.push_back(h.diff(GiNaC::ex_to<GiNaC::symbol>(z.value)));
      row_zp.push_back(z.differential ? h.diff(GiNaC::ex_to<GiNaC::symbol>(z.derivative)) : GiNaC::ex(0));
    }
    for (int k = 0; k < static_cast<int>(scene.inputs.size()); ++k) row_u.push_back(h.diff(scene.jet->input(k)));
    h_z.push_back(std::move(row_z));
    h_zp.push_back(std::move(row_zp));
    h_u.push_back(std::move(row_u));
  }
  const std::size_t n = reduced.components.size();
  dh_dz = add_matrix(*jacobians, h_z, n);
  dh_dzp = add_matrix(*jacobians, h_zp, n);
  dh_du = add_matrix(*jacobians, h_u, scene.inputs.size());
}

std::pair<Eigen::VectorXd, Eigen::VectorXd> Linearizer::Impl::hidden_and_residual(const NumericPoint& p) const {
  const std::vector<double> v = functions->evaluate(program_values(reduced, p), "the residual or a hidden constraint");
  const auto m = static_cast<Eigen::Index>(reduced.hidden.size());
  const Eigen::Map<const Eigen::VectorXd> all(v.data(), static_cast<Eigen::Index>(v.size()));
  return {all.head(m), all.tail(static_cast<Eigen::Index>(v.size()) - m)};
}

Linearizer::~Linearizer() = default;
Linearizer::Linearizer(Linearizer&&) noexcept = default;
Linearizer& Linearizer::operator=(Linearizer&&) noexcept = default;

const Scene& Linearizer::scene() const { return impl_->scene; }
ModelKind Linearizer::model() const { return impl_->model; }
const LinearizeOptions& Linearizer::options() const { return impl_->options; }

namespace {

/// "x''" → ("x", 2).
std::pair<std::string, int> variable_and_order(const std::string& name) {
  std::size_t primes = 0;
  while (primes < name.size() && name[name.size() - 1 - primes] == '\'') ++primes;
  return {name.substr(0, name.size() - primes), static_cast<int>(primes)};
}

}  // namespace

void Linearizer::Impl::setup_turn(const LinearizeOptions::Turn& turn) {
  const std::vector<std::string>& coordinates = scene.jet->coordinates();
  for (const std::string& name : {turn.angle, turn.x, turn.y})
    if (std::find(coordinates.begin(), coordinates.end(), name) == coordinates.end())
      throw InputError({"--turn", 0, 0}, "--turn " + turn.angle + ":" + turn.x + "," + turn.y + ": " + name +
                                             " is not a coordinate of scene " + scene.name);
  if (turn.angle == turn.x || turn.angle == turn.y || turn.x == turn.y)
    throw InputError({"--turn", 0, 0}, "--turn ANGLE:X,Y needs three different coordinates");
  const std::size_t n = reduced.components.size();
  turn_partner.assign(n, -1);
  turn_sign.assign(n, 0.0);
  for (std::size_t c = 0; c < n; ++c) {
    const auto [variable, order] = variable_and_order(reduced.components[c].name);
    if (variable == turn.angle && order == 0) turn_angle = static_cast<int>(c);
    if (variable != turn.x && variable != turn.y) continue;
    const std::string& other = variable == turn.x ? turn.y : turn.x;
    for (std::size_t d = 0; d < n; ++d)
      if (variable_and_order(reduced.components[d].name) == std::make_pair(other, order))
        turn_partner[c] = static_cast<int>(d);
    if (turn_partner[c] < 0)
      throw InputError({"--turn", 0, 0}, "--turn: the reduced system holds " + reduced.components[c].name +
                                             " but not " + base::primed_name(other, order) +
                                             ", which the turn rotates with it: keep both or neither (--keep)");
    turn_sign[c] = variable == turn.x ? -1.0 : 1.0;  // X: x^(k) -> -y^(k), y^(k) -> x^(k)
  }
  if (turn_angle < 0)
    throw InputError({"--turn", 0, 0}, "--turn: " + turn.angle +
                                           " is cyclic, so a steady turn is an equilibrium "
                                           "of the reduced system already: leave --turn out");
}

Eigen::VectorXd Linearizer::Impl::generator(const Eigen::VectorXd& z) const {
  Eigen::VectorXd X = Eigen::VectorXd::Zero(z.size());
  if (!turning()) return X;
  X(turn_angle) = 1.0;
  for (Eigen::Index c = 0; c < z.size(); ++c)
    if (turn_partner[static_cast<std::size_t>(c)] >= 0)
      X(c) = turn_sign[static_cast<std::size_t>(c)] * z(turn_partner[static_cast<std::size_t>(c)]);
  return X;
}

NumericPoint Linearizer::Impl::turned(const NumericPoint& p, double c) const {
  NumericPoint q = p;
  q.z(turn_angle) += c;
  for (Eigen::Index k = 0; k < p.z.size(); ++k) {
    const int partner = turn_partner[static_cast<std::size_t>(k)];
    if (partner < 0) continue;
    // x -> x cos c - y sin c, y -> x sin c + y cos c (turn_sign: -1 on x, +1 on y).
    const double s = turn_sign[static_cast<std::size_t>(k)];
    q.z(k) = std::cos(c) * p.z(k) + s * std::sin(c) * p.z(partner);
    q.zp(k) = std::cos(c) * p.zp(k) + s * std::sin(c) * p.zp(partner);
  }
  return q;
}

void Linearizer::Impl::check_invariant(const NumericPoint& p) const {
  // Equivariance, f(g_c z) = Dg_c f(z): at the point turned by c the hidden constraints hold, and
  // F = 0 solved for the derivatives of the differential states and for the algebraic states (the
  // multipliers, which turn as the constraints are written) gives the turned derivatives.
  const double scale = 1.0 + p.z.cwiseAbs().maxCoeff() + p.zp.cwiseAbs().maxCoeff();
  std::vector<int> differential, algebraic;
  for (std::size_t c = 0; c < reduced.components.size(); ++c)
    (reduced.components[c].differential ? differential : algebraic).push_back(static_cast<int>(c));
  for (const double c : {0.7, 2.3}) {
    const NumericPoint expected = turned(p, c);
    NumericPoint q = expected;
    for (int iteration = 0; iteration < 20; ++iteration) {
      const ManifoldInput in = manifold_input(q);
      Eigen::MatrixXd K(in.dF_dz.rows(), static_cast<Eigen::Index>(differential.size() + algebraic.size()));
      for (std::size_t k = 0; k < differential.size(); ++k)
        K.col(static_cast<Eigen::Index>(k)) = in.dF_dzp.col(differential[k]);
      for (std::size_t k = 0; k < algebraic.size(); ++k)
        K.col(static_cast<Eigen::Index>(differential.size() + k)) = in.dF_dz.col(algebraic[k]);
      const Eigen::VectorXd step = -K.fullPivLu().solve(hidden_and_residual(q).second);
      for (std::size_t k = 0; k < differential.size(); ++k) q.zp(differential[k]) += step(static_cast<Eigen::Index>(k));
      for (std::size_t k = 0; k < algebraic.size(); ++k)
        q.z(algebraic[k]) += step(static_cast<Eigen::Index>(differential.size() + k));
      if (!(step.cwiseAbs().maxCoeff() > 1e-14 * scale)) break;
    }
    const Eigen::VectorXd g = hidden_and_residual(q).first;
    double worst = g.size() ? g.cwiseAbs().maxCoeff() : 0.0;
    for (int k : differential) worst = std::max(worst, std::abs(q.zp(k) - expected.zp(k)));
    if (!(worst <= 1e-8 * scale))
      throw MathError("--turn " + options.turn.angle + ":" + options.turn.x + "," + options.turn.y +
                      ": the equations are not invariant under turning the plane (at the point turned by " + number(c) +
                      " rad the motion differs from the turned motion by " + number(worst) +
                      "), so a steady turn is no relative equilibrium of them");
  }
}

ManifoldInput Linearizer::Impl::manifold_input(const NumericPoint& p) const {
  const std::vector<double> values = jacobians->evaluate(program_values(reduced, p), "dF/dz, dF/dz' or dg/dz");
  ManifoldInput input{matrix_of(dF_dz, values),
                      matrix_of(dF_dzp, values),
                      matrix_of(dg_dz, values),
                      matrix_of(dF_du, values),
                      {},
                      {},
                      {},
                      {},
                      {}};
  for (const ReducedComponent& z : reduced.components) {
    input.differential.push_back(z.differential);
    input.order.push_back(z.order);
    input.multiplier.push_back(z.multiplier);
    input.kept.push_back(z.differential &&
                         std::find(options.states.begin(), options.states.end(), z.name) != options.states.end());
    input.names.push_back(z.name);
  }
  return input;
}

namespace {

void require_size(const std::vector<double>& v, std::size_t n, const std::string& what) {
  if (v.size() != n)
    throw InputError({what, 0, 0},
                     what + " has " + std::to_string(v.size()) + " values; the system has " + std::to_string(n));
}

}  // namespace

std::vector<double> Linearizer::Impl::point_constants(double t, const std::vector<double>& y,
                                                      const std::vector<double>& yp,
                                                      const std::vector<double>& u) const {
  const auto n = static_cast<std::size_t>(system.size());
  require_size(y, n, "y");
  require_size(yp, n, "yp");
  require_size(u, scene.inputs.size(), "u");
  std::vector<double> constants{t};
  constants.insert(constants.end(), scene.parameter_values.begin(), scene.parameter_values.end());
  constants.insert(constants.end(), u.begin(), u.end());
  return constants;
}

Linearization Linearizer::along(double t, const std::vector<double>& y, const std::vector<double>& yp,
                                const std::vector<double>& u) const {
  const Impl& m = *impl_;
  NumericPoint p;
  p.constants = m.point_constants(t, y, yp, u);
  const auto N = static_cast<Eigen::Index>(m.reduced.components.size());
  p.z = Eigen::VectorXd::Zero(N);
  p.zp = Eigen::VectorXd::Zero(N);
  for (Eigen::Index c = 0; c < N; ++c) {
    const auto [k, from_yp] = m.value_source[static_cast<std::size_t>(c)];
    p.z(c) = (from_yp ? yp : y)[static_cast<std::size_t>(k)];
    if (const int d = m.derivative_source[static_cast<std::size_t>(c)]; d >= 0)
      p.zp(c) = yp[static_cast<std::size_t>(d)];
  }
  const ManifoldLinearization lin = linearize_on_manifold(m.manifold_input(p));
  Linearization out;
  out.scene = m.scene.name;
  out.model = m.model;
  out.cyclic = m.reduced.cyclic;
  out.kept = m.reduced.kept;
  m.name_states(lin, out);
  out.A = lin.A;
  out.B = lin.B;
  for (const SceneInput& input : m.scene.inputs) out.inputs.push_back(input.name);
  out.C = Eigen::MatrixXd::Zero(0, out.A.cols());
  out.D = Eigen::MatrixXd::Zero(0, out.B.cols());
  if (!m.options.states.empty()) order_states(out, m.options.states);
  return out;
}

Eigen::MatrixXd Linearizer::input_jacobian(double t, const std::vector<double>& y, const std::vector<double>& yp,
                                           const std::vector<double>& u) const {
  const Impl& m = *impl_;
  std::vector<double> values = m.point_constants(t, y, yp, u);
  values.insert(values.end(), y.begin(), y.end());
  values.insert(values.end(), yp.begin(), yp.end());
  return matrix_of(m.dF_full_du, m.full_input_jacobian->evaluate(values, "dF/du")).array() + 0.0;
}

std::vector<std::string> Linearizer::index1_states() const {
  std::vector<std::string> out;
  for (const StateComponent& s : impl_->system.states) out.push_back(s.name);
  return out;
}

Linearization Linearizer::at(const std::vector<PointOverride>& overrides) const {
  const Impl& m = *impl_;
  if (!m.time_dependence.empty()) throw MathError(m.time_dependence);
  Scene s = m.scene;
  for (const PointOverride& o : overrides) apply_override(s, resolve_override(s, o.name), o.value);

  Linearization out;
  out.scene = s.name;
  out.model = m.model;
  out.cyclic = m.reduced.cyclic;
  out.kept = m.reduced.kept;
  for (const std::string& name : m.options.keep)
    if (std::find(out.kept.begin(), out.kept.end(), name) == out.kept.end())
      out.notes.push_back("--keep " + name + ": " + name + " is not cyclic, so it is a state (or eliminated) anyway");
  const NumericPoint p = m.operating_point(s, out);
  if (m.turning()) {
    out.turn_rate = p.zp(m.turn_angle);
    m.check_invariant(p);
  }
  m.check_stationary(p, out);

  const std::vector<double> jacobians = m.jacobians->evaluate(program_values(m.reduced, p), "dF/dz, dF/dz' or dg/dz");
  const ManifoldLinearization lin = linearize_on_manifold(m.manifold_input(p));
  m.name_states(lin, out);
  out.A = lin.A;
  if (m.turning()) {
    // In the turning frame: A − ω (DX_D T)_s, DX the generator's constant matrix over z_D.
    const auto nD = static_cast<Eigen::Index>(lin.differential.size());
    Eigen::MatrixXd DX = Eigen::MatrixXd::Zero(nD, nD);
    for (Eigen::Index i = 0; i < nD; ++i) {
      const int c = lin.differential[static_cast<std::size_t>(i)];
      const int partner = m.turn_partner[static_cast<std::size_t>(c)];
      for (Eigen::Index j = 0; j < nD && partner >= 0; ++j)
        if (lin.differential[static_cast<std::size_t>(j)] == partner)
          DX(i, j) = m.turn_sign[static_cast<std::size_t>(c)];
    }
    const Eigen::MatrixXd correction = DX * lin.T;
    for (std::size_t r = 0; r < lin.independent.size(); ++r)
      out.A.row(static_cast<Eigen::Index>(r)) -= out.turn_rate * correction.row(lin.independent[r]);
    out.notes.push_back("about a relative equilibrium: A in the frame turning at " + number(out.turn_rate) +
                        " rad/s; families of steady motions are not searched for");
  }
  out.B = lin.B;
  for (const SceneInput& u : s.inputs) out.inputs.push_back(u.name);
  out.outputs = m.output_names;
  for (const std::string& note : m.output_notes) out.notes.push_back(note);
  std::tie(out.C, out.D) = output_matrices(lin, matrix_of(m.dh_dz, jacobians), matrix_of(m.dh_dzp, jacobians),
                                           matrix_of(m.dh_du, jacobians));
  out.manifold_residual = lin.manifold_residual;

  out.eigenvalues = sorted_eigenvalues(out.A);
  out.zero_eigenvalues = count_zero_eigenvalues(out.A, out.eigenvalues, m.options.zero_tolerance);
  if (!m.turning()) out.families = m.families_at(p, lin, out.states, out.zero_eigenvalues);
  out.verdict = classify_spectrum(out.A, out.eigenvalues, static_cast<int>(out.families.size()), m.options.tolerance,
                                  m.options.zero_tolerance);
  if (!m.options.states.empty()) order_states(out, m.options.states);
  return out;
}

LinearizeOptions::Turn parse_turn(const std::string& text, const std::string& flag) {
  const std::size_t colon = text.find(':');
  const std::size_t comma = colon == std::string::npos ? colon : text.find(',', colon + 1);
  if (colon == std::string::npos || comma == std::string::npos || colon == 0 || comma == colon + 1 ||
      comma + 1 == text.size() || text.find(',', comma + 1) != std::string::npos)
    throw InputError({flag, 0, 0}, flag + " " + text + ": expected ANGLE:X,Y (e.g. psi:x,y)");
  return {text.substr(0, colon), text.substr(colon + 1, comma - colon - 1), text.substr(comma + 1)};
}

Linearization linearize(const Scene& scene, ModelKind model, const std::vector<PointOverride>& overrides,
                        const LinearizeOptions& options) {
  return Linearizer(scene, model, options).at(overrides);
}

}  // namespace nhc
