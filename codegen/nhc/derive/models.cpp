#include "nhc/expr/work_stage.hpp"
#include "nhc/derive/models.hpp"

#include <algorithm>
#include <atomic>
#include <set>
#include <utility>

#include "nhc/derive/euler_operator.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

namespace {

using GiNaC::ex;

int sign(int k) { return k % 2 == 0 ? 1 : -1; }  // (−1)^k

std::vector<ex> add_terms(std::vector<ex> base, const std::vector<ex>& extra) {
  for (std::size_t i = 0; i < base.size(); ++i) base[i] += extra[i];
  return base;
}

/// The coordinates q_i^(k) that occur in f, each once, ordered by (i, k).
std::vector<JetCoordinate> occurring_coordinates(const ex& f, const JetSpace& jet) {
  std::set<std::pair<int, int>> seen;
  std::vector<JetCoordinate> out;
  for (const JetCoordinate& c : jet.jet_coordinates_in(f))
    if (c.kind == VariableKind::coordinate && seen.insert({c.index, c.order}).second) out.push_back(c);
  std::sort(out.begin(), out.end(), [](const JetCoordinate& x, const JetCoordinate& y) {
    return std::make_pair(x.index, x.order) < std::make_pair(y.index, y.order);
  });
  return out;
}

std::vector<ex> vakonomic(const MechanicalSystem& s) {
  ex lambda_f = 0;
  for (std::size_t a = 0; a < s.constraints.size(); ++a)
    lambda_f += s.jet.lambda(static_cast<int>(a), 0) * s.constraints[a];
  return add_terms(euler_operator(s.lagrangian, s.jet), euler_operator(lambda_f, s.jet));
}

std::vector<ex> chetaev(const MechanicalSystem& s) {
  std::vector<ex> r = euler_operator(s.lagrangian, s.jet);
  for (std::size_t a = 0; a < s.constraints.size(); ++a) {
    const int alpha = static_cast<int>(a);
    const int m = s.constraint_order(alpha);
    // Only the coordinates whose m-th derivative occurs in f^a contribute (∂f/∂q_i^(m) ≡ 0
    // otherwise): the work per constraint is its own size, not the number of coordinates.
    for (const JetCoordinate& c : occurring_coordinates(s.constraints[a], s.jet))
      if (c.order == m)
        r[static_cast<std::size_t>(c.index)] +=
            s.jet.lambda(alpha, 0) * partial_derivative(s.constraints[a], s.jet.symbol(c));
  }
  return r;
}

std::vector<ex> holder(const MechanicalSystem& s) {
  std::vector<ex> r = euler_operator(s.lagrangian, s.jet);
  for (std::size_t a = 0; a < s.constraints.size(); ++a) {
    const int alpha = static_cast<int>(a);
    const int m = s.constraint_order(alpha);
    for (const JetCoordinate& c : occurring_coordinates(s.constraints[a], s.jet)) {
      const int i = c.index, k = c.order;
      if (k < 1 || k > m) continue;
      {
        const ex partial = partial_derivative(s.constraints[a], s.jet.symbol(c));
        // paper eq. (26): (−1)^{k+1} λ^(k) ∂f/∂q^(k) + ((−1)^{k+1} − 1) λ D^k ∂f/∂q^(k)
        r[static_cast<std::size_t>(i)] +=
            sign(k + 1) * s.jet.lambda(alpha, k) * partial +
            (sign(k + 1) - 1) * s.jet.lambda(alpha, 0) * s.jet.total_derivative(partial, k);
      }
    }
  }
  return r;
}

/// paper eq. (29); returns false with a reason when A = ∂f/∂q'^dep is singular.
bool suslov(const MechanicalSystem& s, std::vector<ex>& r, std::string& reason) {
  const std::size_t g = s.constraints.size();
  r = euler_operator(s.lagrangian, s.jet);
  if (g == 0) return true;
  if (s.dependent.size() != g) {
    reason =
        "the scene names no dependent coordinates (key 'dependent'), which the suslov "
        "model needs, one per constraint";
    return false;
  }
  GiNaC::matrix A(static_cast<unsigned>(g), static_cast<unsigned>(g));
  for (std::size_t a = 0; a < g; ++a)
    for (std::size_t b = 0; b < g; ++b)
      A(static_cast<unsigned>(a), static_cast<unsigned>(b)) =
          partial_derivative(s.constraints[a], s.jet.symbol({VariableKind::coordinate, s.dependent[b], 1}));
  if (work_budget::is_zero(A.determinant())) {
    std::string names;
    for (int d : s.dependent) names += (names.empty() ? "" : ", ") + s.jet.coordinates()[static_cast<std::size_t>(d)];
    reason =
        "the matrix A = ∂f/∂q' of the constraints with respect to the first derivatives of "
        "the dependent coordinates (" +
        names + ") is identically singular";
    return false;
  }
  const GiNaC::matrix A_inv = A.inverse();
  for (std::size_t a = 0; a < g; ++a) {
    ex mu = 0;
    for (std::size_t b = 0; b < g; ++b)
      mu += partial_derivative(s.lagrangian, s.jet.symbol({VariableKind::coordinate, s.dependent[b], 1})) *
            A_inv(static_cast<unsigned>(b), static_cast<unsigned>(a));
    mu = work_budget::normal(mu);
    const std::vector<ex> euler_f = euler_operator(s.constraints[a], s.jet);
    for (std::size_t i = 0; i < r.size(); ++i) r[i] -= mu * euler_f[i];
  }
  return true;
}

}  // namespace

int MechanicalSystem::constraint_order(int alpha) const {
  return jet.highest_coordinate_order(constraints.at(static_cast<std::size_t>(alpha)));
}

namespace {
std::atomic<long> derivations{0};
}  // namespace

long derive_model_calls() { return derivations.load(); }

DerivedModel derive_model(const MechanicalSystem& system, ModelKind kind) {
  ++derivations;
  const work_budget::Stage stage("deriving the equations");
  DerivedModel model;
  model.kind = kind;
  model.constraints = system.constraints;
  std::vector<ex> equations;
  switch (kind) {
    case ModelKind::vakonomic:
      equations = vakonomic(system);
      break;
    case ModelKind::chetaev:
      equations = chetaev(system);
      break;
    case ModelKind::holder:
      equations = holder(system);
      break;
    case ModelKind::suslov:
      model.constraints_are_equations = false;
      if (!suslov(system, equations, model.reason)) {
        model.applicable = false;
        return model;
      }
      break;
  }
  // Generalized non-conservative forces: R_i += Q_i in every model (docs/forces.md).
  for (std::size_t i = 0; i < system.forces.size() && i < equations.size(); ++i) equations[i] += system.forces[i];
  if (model.constraints_are_equations)
    for (std::size_t a = 0; a < system.constraints.size(); ++a)
      model.multipliers.push_back(system.jet.multiplier_name(static_cast<int>(a)));
  for (auto& e : equations) model.equations.push_back(simplify_expression(e));
  return model;
}

}  // namespace nhc
