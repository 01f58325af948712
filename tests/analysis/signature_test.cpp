// σ, c, d, index and dof of the four models for the paper's two examples, each against a hand
// derivation written out below; and the symbolic system Jacobians against hand-derived ones.
#include <catch2/catch.hpp>

#include <random>

#include "analysis_test_support.hpp"
#include "nhc/analysis/system_jacobian.hpp"

using namespace nhc;
using nhc::test::eval;

namespace {

constexpr int X = SignatureMatrix::kAbsent;

struct Expected {
  std::vector<std::vector<int>> sigma;
  std::vector<int> c, d;
  int index, dof;
  std::size_t hidden;  ///< number of hidden constraints = Σ c_i
};

void check(const StructuralAnalysis& a, const Expected& e) {
  REQUIRE_FALSE(a.structurally_singular);
  const int n = static_cast<int>(e.sigma.size());
  REQUIRE(a.sigma.rows() == n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      INFO("sigma(" << a.system.equation_names[static_cast<std::size_t>(i)] << ", "
                    << a.system.unknowns[static_cast<std::size_t>(j)].name << ")");
      CHECK(a.sigma(i, j) == e.sigma[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    }
  CHECK(a.offsets.c == e.c);
  CHECK(a.offsets.d == e.d);
  CHECK(a.index == e.index);
  CHECK(a.dof == e.dof);
  CHECK(a.hidden_constraints.size() == e.hidden);
  // Needed initial values: x_j^(k), k < d_j, Σ d_j of them; value of the transversal = dof.
  std::size_t needed = 0;
  for (int d : e.d) needed += static_cast<std::size_t>(d);
  CHECK(a.initial_values_needed.size() == needed);
  CHECK(a.transversal.value == e.dof);
}

}  // namespace

// ---- Example 1: L = |q'|²/2, f = q'·q'' (n = 3, g = 1) ----------------------------------------
// Unknowns (q1, q2, q3, λ), equations (R_q1, R_q2, R_q3, f1). E_i(L) = −q_i''.

TEST_CASE("particle, vakonomic: index 0, 8 dof", "[sigma]") {
  // E_i(λ f) = −D(λ q_i'') + D²(λ q_i') = λ'' q_i' + λ' q_i''  (the λ q_i''' cancel), so
  // R_i = (λ' − 1) q_i'' + λ'' q_i':  σ(R_i, q_i) = 2, σ(R_i, λ) = 2; f1: σ = 2 in every q.
  // Transversal R1→q1, R2→q2, R3→λ, f1→q3, value 8. c = 0 gives d = (2,2,2,2) with equality
  // on it: canonical. ν = 0 (no d = 0), dof = 8: q, q', λ, λ' all free data, no hidden constraint.
  const Scene s = test::scene_at("examples/particle.toml");
  check(test::structure_of(s, ModelKind::vakonomic),
        {{{2, X, X, 2}, {X, 2, X, 2}, {X, X, 2, 2}, {2, 2, 2, X}}, {0, 0, 0, 0}, {2, 2, 2, 2}, 0, 8, 0});
}

TEST_CASE("particle, chetaev: index 1, 6 dof", "[sigma]") {
  // R_i = −q_i'' + λ ∂f/∂q_i'' = −q_i'' + λ q_i': σ(R_i, q_i) = 2, σ(R_i, λ) = 0.
  // Transversal value 2+2+0+2 = 6; c = 0, d = (2,2,2,0); λ algebraic, so ν = 0 + 1 = 1; dof 6.
  const Scene s = test::scene_at("examples/particle.toml");
  check(test::structure_of(s, ModelKind::chetaev),
        {{{2, X, X, 0}, {X, 2, X, 0}, {X, X, 2, 0}, {2, 2, 2, X}}, {0, 0, 0, 0}, {2, 2, 2, 0}, 1, 6, 0});
}

TEST_CASE("particle, holder: index 1, 10 dof", "[sigma]") {
  // eq. (26) with m = 2: k = 1: λ' q_i''; k = 2: −λ'' q_i' − 2 λ D²(q_i') = −λ'' q_i' − 2λ q_i'''.
  // R_i = (λ' − 1) q_i'' − λ'' q_i' − 2 λ q_i''': σ(R_i, q_i) = 3, σ(R_i, λ) = 2.
  // Transversal R1→q1, R2→q2 (3 each), R3→λ (2), f1→q3 (2): value 10.
  // Iteration: c = 0 → d = (3,3,3,2) → c_f = d_q3 − 2 = 1 → d unchanged. c = (0,0,0,1),
  // d = (3,3,3,2); ν = 1; dof = 11 − 1 = 10; hidden constraint f1 itself.
  const Scene s = test::scene_at("examples/particle.toml");
  check(test::structure_of(s, ModelKind::holder),
        {{{3, X, X, 2}, {X, 3, X, 2}, {X, X, 3, 2}, {2, 2, 2, X}}, {0, 0, 0, 1}, {3, 3, 3, 2}, 1, 10, 1});
}

TEST_CASE("particle, suslov: index 0, 6 dof", "[sigma]") {
  // E_i(f) = −D(q_i'') + D²(q_i') = 0, so R_i = −q_i'': σ = 2 I, c = 0, d = 2, ν = 0, dof 6.
  const Scene s = test::scene_at("examples/particle.toml");
  check(test::structure_of(s, ModelKind::suslov), {{{2, X, X}, {X, 2, X}, {X, X, 2}}, {0, 0, 0}, {2, 2, 2}, 0, 6, 0});
}

// ---- Example 2, Appell–Hamel: L = m/2 |q'|² − m g z, f = z' − k v, v = √(x'² + y'²) ----------
// E(L) = (−m x'', −m y'', −m g − m z''); ∂f/∂x' = −k x'/v, ∂f/∂y' = −k y'/v, ∂f/∂z' = 1.

TEST_CASE("Appell-Hamel, vakonomic: index 1, 6 dof, lambda(0) extra data", "[sigma]") {
  // E_x(λ f) = D(λ k x'/v) = k λ' x'/v + k λ y'(x'' y' − x' y'')/v³ (y alike), E_z(λ f) = −λ'.
  // σ: R_x, R_y: x 2, y 2, λ 1; R_z: z 2, λ 1; f1: x, y, z 1.
  // Transversal R_x→x, R_y→y, R_z→λ, f1→z: 2+2+1+1 = 6. c = 0 → d = (2,2,2,1) → c_f = 1 →
  // d stays: c = (0,0,0,1), d = (2,2,2,1). ν = 1, dof = 7 − 1 = 6, with λ(0) among the data.
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  const StructuralAnalysis a = test::structure_of(s, ModelKind::vakonomic);
  check(a, {{{2, 2, X, 1}, {2, 2, X, 1}, {X, X, 2, 1}, {1, 1, 1, X}}, {0, 0, 0, 1}, {2, 2, 2, 1}, 1, 6, 1});
  CHECK(a.initial_values_needed.back() == JetCoordinate{VariableKind::multiplier, 0, 0});
}

TEST_CASE("Appell-Hamel, chetaev: index 2, 5 dof", "[sigma]") {
  // R_x = −m x'' − λ k x'/v, R_y = −m y'' − λ k y'/v, R_z = −m g − m z'' + λ.
  // σ: R_x: x 2, y 1, λ 0; R_y: x 1, y 2, λ 0; R_z: z 2, λ 0; f1: 1, 1, 1.
  // Transversal R_x→x, R_y→y, R_z→λ, f1→z: 2+2+0+1 = 5. c = (0,0,0,1), d = (2,2,2,0):
  // f1 is differentiated once, λ is algebraic: ν = 1 + 1 = 2; dof = 6 − 1 = 5.
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  check(test::structure_of(s, ModelKind::chetaev),
        {{{2, 1, X, 0}, {1, 2, X, 0}, {X, X, 2, 0}, {1, 1, 1, X}}, {0, 0, 0, 1}, {2, 2, 2, 0}, 2, 5, 1});
}

TEST_CASE("Appell-Hamel, holder: index 1, 6 dof", "[sigma]") {
  // m = 1 in eq. (26): only k = 1, λ' ∂f/∂q' (the λ D(∂f/∂q') term has factor 0):
  // R_x = −m x'' − k λ' x'/v, R_y alike, R_z = −m g − m z'' + λ'. σ as chetaev with λ order 1.
  // c = (0,0,0,1), d = (2,2,2,1); ν = 1; dof = 7 − 1 = 6.
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  check(test::structure_of(s, ModelKind::holder),
        {{{2, 1, X, 1}, {1, 2, X, 1}, {X, X, 2, 1}, {1, 1, 1, X}}, {0, 0, 0, 1}, {2, 2, 2, 1}, 1, 6, 1});
}

TEST_CASE("Appell-Hamel, suslov: index 0, 6 dof", "[sigma]") {
  // Dependent z: A = ∂f/∂z' = 1, μ = ∂L/∂z' = m z'. E_x(f) = k y'(x'' y' − x' y'')/v³,
  // E_y(f) = k x'(x' y'' − y' x'')/v³, E_z(f) = 0. R_x = −m x'' − m z' E_x(f): x 2, y 2, z 1;
  // R_y alike; R_z = −m g − m z'': z 2. c = 0, d = (2,2,2), ν = 0, dof = 6.
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  check(test::structure_of(s, ModelKind::suslov), {{{2, 2, 1}, {2, 2, 1}, {X, X, 2}}, {0, 0, 0}, {2, 2, 2}, 0, 6, 0});
}

TEST_CASE("system Jacobians of Appell-Hamel agree with the hand derivation", "[sigma]") {
  const Scene s = test::scene_at("examples/appell_hamel.toml");
  const JetSpace& jet = *s.jet;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0), pos(0.5, 2.0);
  const GiNaC::ex xd = jet.q(0, 1), yd = jet.q(1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const double m = pos(rng), g = pos(rng), a = pos(rng), b = pos(rng), k = b / a;
    const double vx = u(rng), vy = u(rng), lam = u(rng), v = std::hypot(vx, vy);
    GiNaC::exmap p;
    p[jet.parameter(*jet.parameter_index("m"))] = m;
    p[jet.parameter(*jet.parameter_index("g"))] = g;
    p[jet.parameter(*jet.parameter_index("a"))] = a;
    p[jet.parameter(*jet.parameter_index("b"))] = b;
    p[xd] = vx;
    p[yd] = vy;
    p[jet.lambda(0, 0)] = lam;
    auto numeric = [&](ModelKind kind) {
      const auto jac = system_jacobian(test::structure_of(s, kind));
      Eigen::Matrix4d out;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out(i, j) = eval(jac[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)], p);
      return out;
    };
    // chetaev: columns (x'', y'', z'', λ), rows R_x, R_y, R_z and D f1 (in x', y', z').
    Eigen::Matrix4d chetaev;
    chetaev << -m, 0, 0, -k * vx / v,  //
        0, -m, 0, -k * vy / v,         //
        0, 0, -m, 1,                   //
        -k * vx / v, -k * vy / v, 1, 0;
    CHECK((numeric(ModelKind::chetaev) - chetaev).cwiseAbs().maxCoeff() < 1e-12);
    // det = (−m)³ · (1 + k²)/m = −m² (1 + k²): never singular.
    CHECK(chetaev.determinant() == Approx(-m * m * (1 + k * k)));
    // vakonomic: columns (x'', y'', z'', λ').
    Eigen::Matrix4d vak;
    const double v3 = v * v * v;
    vak << -m + k * lam * vy * vy / v3, -k * lam * vx * vy / v3, 0, k * vx / v,  //
        -k * lam * vx * vy / v3, -m + k * lam * vx * vx / v3, 0, k * vy / v,     //
        0, 0, -m, -1,                                                            //
        -k * vx / v, -k * vy / v, 1, 0;
    const Eigen::Matrix4d vak_n = numeric(ModelKind::vakonomic);
    CHECK((vak_n - vak).cwiseAbs().maxCoeff() < 1e-10);
    // Rotating x' onto v: det = −m (1 + k²)(−m + k λ / v), zero exactly where m v = λ k.
    CHECK(vak_n.determinant() == Approx(-m * (1 + k * k) * (-m + k * lam / v)).epsilon(1e-9));
  }
}
