// The index-1 claim, numerically: at random consistent points of every model of both examples,
// the reduced system F(t, y, y') = 0 holds, its hidden constraints vanish, and IDA's iteration
// matrix G = dF/dy + c_j dF/dy' is nonsingular for small steps h = 1/c_j. With the algebraic
// columns left as they are and the differential ones scaled by h, G tends as h → 0 to
// A = [dF/dy' (differential components) | dF/dy (algebraic components)], whose nonsingularity is
// the index-1 condition; every evaluation is GiNaC's evalf of the Index1System expressions.
#include <catch2/catch.hpp>

#include <random>

#include "analysis_test_support.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/errors.hpp"

using namespace nhc;
using nhc::test::eval;

namespace {

struct Matrices {
  Eigen::MatrixXd dy, dyp;
  Eigen::VectorXd residual, hidden;
};

GiNaC::exmap state_point(const Scene& s, const Index1System& sys, const std::vector<double>& y,
                         const std::vector<double>& yp) {
  GiNaC::exmap p = s.parameter_substitution();
  p[sys.jet->time()] = s.initial.t0;
  for (int k = 0; k < sys.size(); ++k) {
    p[sys.y[static_cast<std::size_t>(k)]] = y[static_cast<std::size_t>(k)];
    p[sys.yp[static_cast<std::size_t>(k)]] = yp[static_cast<std::size_t>(k)];
  }
  return p;
}

Matrices evaluate(const Index1System& sys, const GiNaC::exmap& p) {
  const auto n = static_cast<Eigen::Index>(sys.size());
  Matrices m{Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, n), Eigen::VectorXd(n),
             Eigen::VectorXd(static_cast<Eigen::Index>(sys.hidden_constraints.size()))};
  for (Eigen::Index i = 0; i < n; ++i) {
    const GiNaC::ex& f = sys.residuals[static_cast<std::size_t>(i)];
    m.residual(i) = eval(f, p);
    for (Eigen::Index k = 0; k < n; ++k) {
      m.dy(i, k) = eval(f.diff(sys.y[static_cast<std::size_t>(k)]), p);
      m.dyp(i, k) = eval(f.diff(sys.yp[static_cast<std::size_t>(k)]), p);
    }
  }
  for (std::size_t h = 0; h < sys.hidden_constraints.size(); ++h) {
    m.hidden(static_cast<Eigen::Index>(h)) = eval(sys.hidden_constraints[h], p);
    // The stored Jacobian of the hidden constraint is its derivative in y.
    for (int k = 0; k < sys.size(); ++k)
      CHECK(eval(sys.hidden_constraint_derivative(h, k), p) ==
            Approx(eval(sys.hidden_constraints[h].diff(sys.y[static_cast<std::size_t>(k)]), p)).margin(1e-12));
  }
  return m;
}

/// A = [dF/dy' | dF/dy] by component kind, and G(h)·diag(h on differential components).
Eigen::MatrixXd index1_matrix(const Index1System& sys, const Matrices& m, double h) {
  Eigen::MatrixXd g = m.dy + (h > 0 ? 1.0 / h : 0.0) * m.dyp;
  if (h == 0) g = m.dy;
  for (int k = 0; k < sys.size(); ++k) {
    if (!sys.states[static_cast<std::size_t>(k)].differential) continue;
    g.col(k) = h > 0 ? Eigen::VectorXd(h * m.dy.col(k) + m.dyp.col(k)) : Eigen::VectorXd(m.dyp.col(k));
  }
  return g;
}

/// Random initial data for every needed value, then the nearest consistent point.
std::optional<ConsistentPoint> random_consistent_point(Scene& s, const StructuralAnalysis& a, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  s.initial.values.clear();
  for (int j = 0; j < a.system.size(); ++j) {
    std::vector<double> v(static_cast<std::size_t>(a.d(j)));
    for (double& x : v) {
      x = u(rng);
      if (std::abs(x) < 0.3) x += x < 0 ? -0.5 : 0.5;  // keep away from the λ = 0, v = 0 singularities
    }
    if (!v.empty()) s.initial.values[a.system.unknowns[static_cast<std::size_t>(j)].name] = v;
  }
  InitializationOptions options;
  options.repair = true;
  try {
    ConsistentPoint p = consistent_initial_point(s, a, options);
    if (!p.leading_solved) return std::nullopt;
    return p;
  } catch (const MathError&) {
    return std::nullopt;
  }
}

}  // namespace

TEST_CASE("reduced systems are index 1 at random consistent points", "[sigma]") {
  std::mt19937 rng(42);
  for (const char* path : {"examples/particle.toml", "examples/appell_hamel.toml"}) {
    for (ModelKind kind : kAllModels) {
      Scene s = test::scene_at(path);
      const DerivedModel model = derive_model(s, kind);
      if (!model.applicable) continue;
      const StructuralAnalysis a = analyze_structure(dae_system_of(s, model));
      const Index1System sys = reduce_to_index1(a);
      INFO(path << " " << to_string(kind));
      // Layout: Σ max(d_j, 1) states, as many residuals, one hidden constraint per D^r f_i
      // (suslov: per monitored constraint on initial data).
      int expected_states = 0;
      for (int d : a.offsets.d) expected_states += std::max(d, 1);
      REQUIRE(sys.size() == expected_states);
      REQUIRE(sys.residuals.size() == sys.states.size());
      REQUIRE(sys.hidden_constraints.size() == initial_value_constraints(a).size());
      if (kind != ModelKind::suslov) REQUIRE(sys.hidden_constraints.size() == a.hidden_constraints.size());
      int good = 0;
      for (int trial = 0; trial < 40 && good < 6; ++trial) {
        const auto p = random_consistent_point(s, a, rng);
        if (!p) continue;
        std::vector<double> y0, yp0;
        initial_state(sys, *p, y0, yp0);
        const Matrices m = evaluate(sys, state_point(s, sys, y0, yp0));
        CHECK(m.residual.cwiseAbs().maxCoeff() < 1e-8);
        if (m.hidden.size() > 0) CHECK(m.hidden.cwiseAbs().maxCoeff() < 1e-8);
        const double limit = test::cond(index1_matrix(sys, m, 0.0));
        if (limit > 1e8) continue;  // a random point near a singular one (e.g. m v ≈ λ k)
        ++good;
        for (double h : {1e-2, 1e-4, 1e-6, 1e-8}) {
          const Eigen::MatrixXd g = index1_matrix(sys, m, h);
          CHECK(test::smallest_singular_value(g) > 0.0);
          CHECK(test::cond(g) < 10 * limit + 1e3);
          // Unscaled G = dF/dy + c_j dF/dy' is nonsingular too, its condition O(c_j) (index 1).
          const Eigen::MatrixXd full = m.dy + (1.0 / h) * m.dyp;
          CHECK(test::cond(full) * h < 1e6 * (1 + limit));
        }
      }
      CHECK(good >= 5);
    }
  }
}

TEST_CASE("the iteration matrix is singular where the system Jacobian is", "[sigma]") {
  // Holder particle at λ = 0 (examples/particle.toml): J singular, so A is.
  Scene s = test::scene_at("examples/particle.toml");
  const StructuralAnalysis a = test::structure_of(s, ModelKind::holder);
  const Index1System sys = reduce_to_index1(a);
  const ConsistentPoint p = consistent_initial_point(s, a);
  std::vector<double> y0, yp0;
  initial_state(sys, p, y0, yp0);
  const Matrices m = evaluate(sys, state_point(s, sys, y0, yp0));
  CHECK(test::cond(index1_matrix(sys, m, 0.0)) > 1e12);
}

TEST_CASE("chetaev Appell-Hamel reduced layout", "[sigma]") {
  // d = (2,2,2,0): states x, x', y, y', z, z', λ (algebraic); residuals R_x, R_y, R_z, D f1,
  // chain rows for x, y, z; one hidden constraint f1 = z' − k v in y.
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  const Index1System sys = reduce_to_index1(s, derive_model(s, ModelKind::chetaev));
  REQUIRE(sys.size() == 7);
  CHECK_FALSE(sys.states[6].differential);
  CHECK(sys.states[6].kind == VariableKind::multiplier);
  for (int k = 0; k < 6; ++k) CHECK(sys.states[static_cast<std::size_t>(k)].differential);
  CHECK(sys.residual_names[3] == "D f1");
  CHECK(sys.residual_names[4] == "chain x' = x'");
  REQUIRE(sys.hidden_constraints.size() == 1);
  // f1 with z' = y[5], x' = y[1], y' = y[3]: z' − (b/a) sqrt(x'^2 + y'^2).
  const JetSpace& jet = *sys.jet;
  const GiNaC::ex a = jet.parameter(*jet.parameter_index("a")), b = jet.parameter(*jet.parameter_index("b"));
  const GiNaC::ex expected = sys.y[5] - b / a * GiNaC::sqrt(GiNaC::pow(sys.y[1], 2) + GiNaC::pow(sys.y[3], 2));
  CHECK((sys.hidden_constraints[0] - expected).normal().is_zero());
  // The chain row of x: yp[0] − y[1].
  CHECK((sys.residuals[4] - (sys.yp[0] - sys.y[1])).is_zero());
}
