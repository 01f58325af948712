// The four models: their reduction to the paper's first-order equations (6), (8), (10) for
// generic L and f (undetermined GiNaC functions), the higher-order forms (22) and (26), and the
// facts about the paper's two examples listed in models.md. Each expected value is computed
// independently of nhc's model code (direct formulas, closed-form motions), never copied from
// its output.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/derive/euler_operator.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

using GiNaC::ex;
using nhc::DerivedModel;
using nhc::JetSpace;
using nhc::MechanicalSystem;
using nhc::ModelKind;
using nhc::VariableKind;

namespace {

DECLARE_FUNCTION_7P(model_test_L)
DECLARE_FUNCTION_7P(model_test_f)
DECLARE_FUNCTION_7P(model_test_g)
DECLARE_FUNCTION_5P(model_test_phi1)
DECLARE_FUNCTION_5P(model_test_phi2)
REGISTER_FUNCTION(model_test_L, dummy())
REGISTER_FUNCTION(model_test_f, dummy())
REGISTER_FUNCTION(model_test_g, dummy())
REGISTER_FUNCTION(model_test_phi1, dummy())
REGISTER_FUNCTION(model_test_phi2, dummy())

bool same(const ex& a, const ex& b) {
  const ex d = (a - b).expand();
  return d.is_zero() || d.normal().is_zero();
}

const GiNaC::symbol& sym(const ex& e) { return GiNaC::ex_to<GiNaC::symbol>(e); }

/// [F]_i = ∂F/∂q_i − D ∂F/∂q_i', written out directly.
ex bracket(const ex& F, const JetSpace& jet, int i) {
  return F.diff(sym(jet.q(i, 0))) - jet.total_derivative(F.diff(sym(jet.q(i, 1))));
}

/// A 3-coordinate jet with a generic first-order L and two generic first-order constraints.
struct GenericFirstOrder {
  JetSpace jet{{"q1", "q2", "q3"}, 2, {}};
  ex L, f1, f2;
  GenericFirstOrder() {
    const ex t = jet.time();
    auto q = [&](int i, int k) { return jet.q(i, k); };
    L = model_test_L(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1), q(1, 1), q(2, 1));
    f1 = model_test_f(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1), q(1, 1), q(2, 1));
    f2 = model_test_g(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1), q(1, 1), q(2, 1));
  }
};

std::string scene_dir() { return std::string(NHC_SOURCE_DIR) + "/examples/"; }

/// Puts the horizontal velocity on a rational parametrisation of its circle,
/// x' = V (1 − s²)/(1 + s²), y' = 2 V s/(1 + s²) with V > 0, so that
/// sqrt(x'^2 + y'^2) = V exactly and normal() sees cancellations through the radical.
ex on_speed_circle(const ex& e, const JetSpace& jet) {
  static const GiNaC::possymbol V("V");
  static const GiNaC::realsymbol s("s");
  GiNaC::exmap m;
  m[jet.q(0, 1)] = V * (1 - s * s) / (1 + s * s);
  m[jet.q(1, 1)] = 2 * V * s / (1 + s * s);
  return e.subs(m).normal().normal();  // the second pass cancels through the radicals removed by the first
}

}  // namespace

TEST_CASE("m = 1: vakonomic is eq. (6)", "[derive][models]") {
  GenericFirstOrder s;
  const MechanicalSystem sys{s.jet, s.L, {s.f1, s.f2}, {}};
  const DerivedModel model = nhc::derive_model(sys, ModelKind::vakonomic);
  REQUIRE(model.applicable);
  REQUIRE(model.equations.size() == 3);
  const std::vector<ex> f = {s.f1, s.f2};
  for (int i = 0; i < 3; ++i) {
    // (6): [L]_i + λ_α (∂f^α/∂q_i − D ∂f^α/∂q_i') − λ'_α ∂f^α/∂q_i' = 0
    ex expected = bracket(s.L, s.jet, i);
    for (int a = 0; a < 2; ++a)
      expected += s.jet.lambda(a, 0) * bracket(f[a], s.jet, i) - s.jet.lambda(a, 1) * f[a].diff(sym(s.jet.q(i, 1)));
    CHECK(same(model.equations[i], expected));
  }
  CHECK(model.constraints_are_equations);
  CHECK(model.multipliers == std::vector<std::string>{"lambda1", "lambda2"});
}

TEST_CASE("m = 1: chetaev is eq. (8) with Λ = −λ, holder is eq. (8) with Λ = −λ'", "[derive][models]") {
  GenericFirstOrder s;
  const MechanicalSystem sys{s.jet, s.L, {s.f1, s.f2}, {}};
  const DerivedModel chetaev = nhc::derive_model(sys, ModelKind::chetaev);
  const DerivedModel holder = nhc::derive_model(sys, ModelKind::holder);
  const std::vector<ex> f = {s.f1, s.f2};
  for (int i = 0; i < 3; ++i) {
    // (8): [L]_i − Λ_α ∂f^α/∂q_i' = 0
    ex with_lambda = bracket(s.L, s.jet, i), with_lambda_dot = bracket(s.L, s.jet, i);
    for (int a = 0; a < 2; ++a) {
      const ex grad = f[a].diff(sym(s.jet.q(i, 1)));
      with_lambda -= (-s.jet.lambda(a, 0)) * grad;
      with_lambda_dot -= (-s.jet.lambda(a, 1)) * grad;
    }
    CHECK(same(chetaev.equations[i], with_lambda));
    CHECK(same(holder.equations[i], with_lambda_dot));
  }
}

TEST_CASE("m = 1, f = q'^α − φ^α: suslov is eq. (10)", "[derive][models]") {
  JetSpace jet({"q1", "q2", "q3"}, 2, {});
  const ex t = jet.time();
  auto q = [&](int i, int k) { return jet.q(i, k); };
  const ex L = model_test_L(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1), q(1, 1), q(2, 1));
  // Dependent q2, q3; φ^α(t, q, q'^μ) with the independent velocity q1'.
  const ex f1 = q(1, 1) - model_test_phi1(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1));
  const ex f2 = q(2, 1) - model_test_phi2(t, q(0, 0), q(1, 0), q(2, 0), q(0, 1));
  const MechanicalSystem sys{jet, L, {f1, f2}, {1, 2}};
  const DerivedModel model = nhc::derive_model(sys, ModelKind::suslov);
  REQUIRE(model.applicable);
  CHECK(!model.constraints_are_equations);
  CHECK(model.multipliers.empty());
  for (int i = 0; i < 3; ++i) {
    // (10): [L]_i − ∂L/∂q'^α (∂f^α/∂q_i − D ∂f^α/∂q_i') = 0
    const ex expected =
        bracket(L, jet, i) - L.diff(sym(q(1, 1))) * bracket(f1, jet, i) - L.diff(sym(q(2, 1))) * bracket(f2, jet, i);
    CHECK(same(model.equations[i], expected));
  }
}

TEST_CASE("m = 2: vakonomic is eq. (22), holder is eq. (26), chetaev uses ∂f/∂q^(m)", "[derive][models]") {
  JetSpace jet({"q1", "q2"}, 1, {});
  const ex t = jet.time();
  auto q = [&](int i, int k) { return jet.q(i, k); };
  const ex L = model_test_L(t, q(0, 0), q(1, 0), q(0, 1), q(1, 1), t, t);
  const ex f = model_test_f(t, q(0, 0), q(1, 0), q(0, 1), q(1, 1), q(0, 2), q(1, 2));
  const MechanicalSystem sys{jet, L, {f}, {}};
  const ex lam = jet.lambda(0, 0);
  const DerivedModel vak = nhc::derive_model(sys, ModelKind::vakonomic);
  const DerivedModel che = nhc::derive_model(sys, ModelKind::chetaev);
  const DerivedModel hol = nhc::derive_model(sys, ModelKind::holder);
  for (int i = 0; i < 2; ++i) {
    const ex EL = bracket(L, jet, i);
    ex e22 = EL, e26 = EL;
    for (int k = 0; k <= 2; ++k)  // (22): [L]_i + Σ_{k=0}^m (−1)^k D^k(λ ∂f/∂q_i^(k))
      e22 += (k % 2 ? -1 : 1) * jet.total_derivative(lam * f.diff(sym(q(i, k))), k);
    for (int k = 1; k <= 2; ++k) {  // (26) as printed
      const ex p = f.diff(sym(q(i, k)));
      const int s = (k + 1) % 2 ? -1 : 1;
      e26 += s * jet.lambda(0, k) * p + (s - 1) * lam * jet.total_derivative(p, k);
    }
    CHECK(same(vak.equations[i], e22));
    CHECK(same(hol.equations[i], e26));
    CHECK(same(che.equations[i], EL + lam * f.diff(sym(q(i, 2)))));
  }
}

TEST_CASE("Example 1 (particle): the facts of models.md", "[derive][models][paper]") {
  const nhc::Scene scene = nhc::load_scene(scene_dir() + "particle.toml");
  const JetSpace& jet = *scene.jet;
  const ex lam = jet.lambda(0, 0), lam1 = jet.lambda(0, 1), lam2 = jet.lambda(0, 2);
  const ex f = scene.constraints[0];

  SECTION("vakonomic: (λ' − 1) q'' + λ'' q' = 0 up to sign; the λ q''' terms cancel") {
    const DerivedModel m = nhc::derive_model(scene, ModelKind::vakonomic);
    int sign = 0;
    for (int i = 0; i < 3; ++i) {
      const ex expected = (lam1 - 1) * jet.q(i, 2) + lam2 * jet.q(i, 1);
      if (sign == 0) sign = same(m.equations[i], expected) ? 1 : -1;
      CHECK(same(m.equations[i], sign * expected));
      CHECK(jet.highest_coordinate_order(m.equations[i]) == 2);  // no q''' left
      CHECK(!m.equations[i].has(jet.q(i, 3)));
    }
  }
  SECTION("chetaev: q'' = λ q', so on f = 0 λ = 0 and the motion is uniform") {
    const DerivedModel m = nhc::derive_model(scene, ModelKind::chetaev);
    ex contracted = 0, speed2 = 0;
    for (int i = 0; i < 3; ++i) {
      CHECK(same(m.equations[i] * m.equations[i], GiNaC::pow(jet.q(i, 2) - lam * jet.q(i, 1), 2)));
      contracted += jet.q(i, 1) * m.equations[i];
      speed2 += GiNaC::pow(jet.q(i, 1), 2);
    }
    // Σ q_i' R_i = ∓(f − λ |q'|²): with f = 0 and q' ≠ 0, λ = 0.
    CHECK((same(contracted, lam * speed2 - f) || same(contracted, f - lam * speed2)));
  }
  SECTION("holder: eq. (26) as printed, −q'' + λ'q'' − λ''q' − 2λq''' with L = |q'|²/2") {
    const DerivedModel m = nhc::derive_model(scene, ModelKind::holder);
    for (int i = 0; i < 3; ++i)
      CHECK(same(m.equations[i], -jet.q(i, 2) + lam1 * jet.q(i, 2) - lam2 * jet.q(i, 1) - 2 * lam * jet.q(i, 3)));
  }
  SECTION("suslov: E_i(f) vanishes identically for f = q'·q'', leaving free motion") {
    for (const ex& e : nhc::euler_operator_closed_form(f, jet)) CHECK(e.is_zero());
    const DerivedModel m = nhc::derive_model(scene, ModelKind::suslov);
    REQUIRE(m.applicable);
    for (int i = 0; i < 3; ++i) CHECK(same(m.equations[i], -jet.q(i, 2)));
  }
}

TEST_CASE("Example 2 (Appell–Hamel), chetaev: the closed-form motion solves it", "[derive][models][paper]") {
  const nhc::Scene scene = nhc::load_scene(scene_dir() + "appell_hamel.toml");
  const JetSpace& jet = *scene.jet;
  const DerivedModel m = nhc::derive_model(scene, ModelKind::chetaev);
  REQUIRE(m.applicable);

  // Positive symbols for the parameters and the current speed v(t) > 0 (before t*).
  GiNaC::possymbol pm("m"), pg("g"), pa("a"), pb("b"), V("V");
  GiNaC::exmap to_pos;
  for (const auto& [name, value] : std::vector<std::pair<std::string, ex>>{{"m", pm}, {"g", pg}, {"a", pa}, {"b", pb}})
    to_pos[jet.parameter(*jet.parameter_index(name))] = value;
  const ex k = pb / pa;
  const ex v_dot = -pg * k / (1 + k * k);         // v' = −g k/(1 + k²)
  const ex lambda_exact = pm * pg / (1 + k * k);  // λ = m g/(1 + k²)
  // Constant horizontal direction (3/5, 4/5); z' = k v.
  const GiNaC::numeric c(3, 5), s(4, 5);
  GiNaC::exmap motion = to_pos;
  motion[jet.q(0, 1)] = c * V;
  motion[jet.q(1, 1)] = s * V;
  motion[jet.q(2, 1)] = k * V;
  motion[jet.q(0, 2)] = c * v_dot;
  motion[jet.q(1, 2)] = s * v_dot;
  motion[jet.q(2, 2)] = k * v_dot;
  motion[jet.lambda(0, 0)] = lambda_exact;
  for (const ex& r : m.equations) CHECK(r.subs(motion).normal().is_zero());
  CHECK(m.constraints[0].subs(motion).normal().is_zero());

  SECTION("a different λ does not solve it") {
    GiNaC::exmap wrong = motion;
    wrong[jet.lambda(0, 0)] = 2 * lambda_exact;
    CHECK(!m.equations[2].subs(wrong).normal().is_zero());
  }

  SECTION("v reaches 0 at t* = v0 (a² + b²)/(g a b)") {
    GiNaC::possymbol v0("v0");
    const ex t_star = v0 * (pa * pa + pb * pb) / (pg * pa * pb);
    CHECK((v0 + v_dot * t_star).normal().is_zero());
  }
}

TEST_CASE("Example 2 (Appell–Hamel), chetaev: energy is conserved", "[derive][models][paper]") {
  const nhc::Scene scene = nhc::load_scene(scene_dir() + "appell_hamel.toml");
  const JetSpace& jet = *scene.jet;
  const DerivedModel m = nhc::derive_model(scene, ModelKind::chetaev);
  REQUIRE(scene.invariants.size() == 1);
  const ex E = scene.invariants[0].expression;
  // On the jet: D(E) = −Σ q_i' R_i + λ f, so D(E) = 0 wherever R = 0 and f = 0.
  ex contracted = 0;
  for (int i = 0; i < 3; ++i) contracted += jet.q(i, 1) * m.equations[i];
  CHECK(on_speed_circle(jet.total_derivative(E) + contracted - jet.lambda(0, 0) * scene.constraints[0], jet).is_zero());

  // Along the closed-form motion, E(t) is constant (E is polynomial in the velocities).
  const GiNaC::realsymbol t = jet.time();
  GiNaC::possymbol pm("m"), pg("g"), pa("a"), pb("b"), v0("v0"), z0("z0");
  GiNaC::exmap p;
  for (const auto& [name, value] : std::vector<std::pair<std::string, ex>>{{"m", pm}, {"g", pg}, {"a", pa}, {"b", pb}})
    p[jet.parameter(*jet.parameter_index(name))] = value;
  const ex k = pb / pa, c = pg * k / (1 + k * k), v = v0 - c * t;
  GiNaC::exmap motion = p;
  motion[jet.q(0, 1)] = GiNaC::numeric(3, 5) * v;
  motion[jet.q(1, 1)] = GiNaC::numeric(4, 5) * v;
  motion[jet.q(2, 1)] = k * v;
  motion[jet.q(2, 0)] = z0 + k * (v0 * t - c * t * t / 2);
  const ex E_t = E.subs(motion);
  CHECK(E_t.diff(t).normal().is_zero());
}

TEST_CASE("Example 2 (Appell–Hamel), vakonomic: singular where m v = λ k", "[derive][models][paper]") {
  const nhc::Scene scene = nhc::load_scene(scene_dir() + "appell_hamel.toml");
  const JetSpace& jet = *scene.jet;
  const DerivedModel m = nhc::derive_model(scene, ModelKind::vakonomic);
  // Leading unknowns x'', y'', z'', λ'; equations R_x, R_y, R_z and D f.
  std::vector<ex> rows = m.equations;
  rows.push_back(jet.total_derivative(scene.constraints[0]));
  const std::vector<ex> unknowns = {jet.q(0, 2), jet.q(1, 2), jet.q(2, 2), jet.lambda(0, 1)};
  GiNaC::matrix J(4, 4);
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) J(r, c) = rows[r].diff(sym(unknowns[c]));
  const ex det = J.determinant().normal();
  CHECK(!det.is_zero());
  const ex pm = jet.parameter(*jet.parameter_index("m"));
  const ex pa = jet.parameter(*jet.parameter_index("a"));
  const ex pb = jet.parameter(*jet.parameter_index("b"));
  const ex v = GiNaC::sqrt(GiNaC::pow(jet.q(0, 1), 2) + GiNaC::pow(jet.q(1, 1), 2));
  // λ = m v / k makes the leading matrix singular ...
  CHECK(on_speed_circle(det.subs(jet.lambda(0, 0) == pm * v * pa / pb), jet).is_zero());
  // ... and no other value of λ does: det is a nonzero multiple of (m v − λ k).
  const ex ratio = on_speed_circle(det / (pm * v - jet.lambda(0, 0) * pb / pa), jet);
  CHECK(!ratio.is_zero());
  CHECK(!ratio.has(jet.lambda(0, 0)));
}

TEST_CASE("suslov is reported as not applicable, with the reason", "[derive][models]") {
  SECTION("no dependent coordinates") {
    const nhc::Scene s = nhc::parse_scene(
        "name = \"p\"\ncoordinates = [\"x\", \"y\"]\nlagrangian = \"(x'^2 + y'^2)/2\"\n"
        "constraints = [\"x'*x'' + y'*y''\"]\n",
        "p.toml");
    const DerivedModel m = nhc::derive_model(s, ModelKind::suslov);
    CHECK(!m.applicable);
    CHECK(m.reason.find("dependent") != std::string::npos);
    CHECK(nhc::derive_model(s, ModelKind::chetaev).applicable);
  }
  SECTION("∂f/∂q'^dep identically zero") {
    const nhc::Scene s = nhc::parse_scene(
        "name = \"p\"\ncoordinates = [\"x\", \"y\", \"z\"]\nlagrangian = \"(x'^2 + y'^2)/2\"\n"
        "constraints = [\"x'*y'' - y'*x''\"]\ndependent = [\"z\"]\n",
        "p.toml");
    const DerivedModel m = nhc::derive_model(s, ModelKind::suslov);
    CHECK(!m.applicable);
    CHECK(m.reason.find("singular") != std::string::npos);
  }
  SECTION("∂f/∂q'^dep singular as a matrix although no entry vanishes") {
    const nhc::Scene s = nhc::parse_scene(
        "name = \"p\"\ncoordinates = [\"x\", \"y\", \"z\"]\nlagrangian = \"(x'^2 + y'^2 + z'^2)/2\"\n"
        "constraints = [\"y' + z' - x\", \"2*y' + 2*z' - x^2\"]\ndependent = [\"y\", \"z\"]\n",
        "p.toml");
    const DerivedModel m = nhc::derive_model(s, ModelKind::suslov);
    CHECK(!m.applicable);
  }
}
