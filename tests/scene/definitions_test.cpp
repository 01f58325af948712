// The scene language beyond scalars: vectors, matrices, rotations and angular velocities,
// [definitions] and [forces]. Angular velocities composed in closed form (value.hpp) are checked
// against the definition Ṙ Rᵀ = [ω]× evaluated entry by entry on literal matrices.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/scene_builder.hpp"

using GiNaC::ex;
using nhc::JetSpace;
using nhc::parse_expression;
using nhc::parse_value;

namespace {

JetSpace make_jet() { return JetSpace({"x", "y", "z"}, 0, {"m", "r"}); }

bool same(const ex& a, const ex& b) { return (a - b).expand().normal().is_zero(); }

/// True when a and b agree at a few points (trigonometric identities GiNaC does not apply).
bool same_numerically(const ex& a, const ex& b, const JetSpace& jet) {
  for (int trial = 0; trial < 3; ++trial) {
    GiNaC::exmap point;
    for (int i = 0; i < jet.coordinate_count(); ++i)
      for (int k = 0; k <= 2; ++k) point[jet.q(i, k)] = 0.3 + 0.7 * i - 0.4 * k + 0.37 * trial;
    point[jet.parameter(0)] = 1.3;
    point[jet.parameter(1)] = 0.7;
    point[jet.time()] = 0.2;
    for (int alpha = 0; alpha < jet.multiplier_count(); ++alpha) point[jet.lambda(alpha, 0)] = 0.9;
    const ex d = GiNaC::evalf((a - b).subs(point));
    if (!GiNaC::is_a<GiNaC::numeric>(d) || std::abs(GiNaC::ex_to<GiNaC::numeric>(d).to_double()) > 1e-12) return false;
  }
  return true;
}

std::string rotation_literal(const std::string& axis, const std::string& a) {
  const std::string c = "cos(" + a + ")", s = "sin(" + a + ")";
  if (axis == "x") return "[[1, 0, 0], [0, " + c + ", -" + s + "], [0, " + s + ", " + c + "]]";
  if (axis == "y") return "[[" + c + ", 0, " + s + "], [0, 1, 0], [-" + s + ", 0, " + c + "]]";
  return "[[" + c + ", -" + s + ", 0], [" + s + ", " + c + ", 0], [0, 0, 1]]";
}

}  // namespace

TEST_CASE("vectors and matrices: literals, products, indexing", "[scene][definitions]") {
  const JetSpace jet = make_jet();
  const ex x = jet.q(0, 0), y = jet.q(1, 0), z = jet.q(2, 0);
  CHECK(same(parse_expression("dot([x, y, z], [1, 2, 3])", jet), x + 2 * y + 3 * z));
  CHECK(same(parse_expression("cross([x, y, z], [1, 0, 0])[2]", jet), z));
  CHECK(same(parse_expression("cross([x, y, z], [1, 0, 0])[3]", jet), -y));
  CHECK(same(parse_expression("norm([3, 4])", jet), 5));
  CHECK(same(parse_expression("([[1, 2], [3, 4]]*[x, y])[2]", jet), 3 * x + 4 * y));
  CHECK(same(parse_expression("(transpose([[1, 2], [3, 4]])*[[x, 0], [0, y]])[1, 2]", jet), 3 * y));
  CHECK(same(parse_expression("([x, y] - 2*[y, x]/2)[1]", jet), x - y));
  CHECK(same(parse_expression("[x, y][1]^2", jet), x * x));
  const nhc::Value v = parse_value("[[x, y, z], [1, 2, 3]]", jet);
  CHECK((v.rows == 2 && v.cols == 3));
  CHECK_THROWS_AS(parse_expression("[x, y]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("[x, y][0]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("[x, y][1.5]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("dot([x, y, z], [x, y])", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("cross([x, y], [x, y])[1]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("sin([x, y])", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("[x, y]^2", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("x/[x, y]", jet), nhc::ExpressionSyntaxError);
}

TEST_CASE("angular velocities in closed form agree with R' R^T of the literal matrices", "[scene][definitions]") {
  const JetSpace jet = make_jet();
  const std::string composed = "rotz(x)*rotx(y)*roty(z + t)";
  const std::string literal = "(" + rotation_literal("z", "x") + ")*(" + rotation_literal("x", "y") + ")*(" +
                              rotation_literal("y", "z + t") + ")";
  for (const char* f : {"omega", "omega_body"})
    for (int k = 1; k <= 3; ++k) {
      const std::string index = "[" + std::to_string(k) + "]";
      INFO(f << index);
      const ex closed = parse_expression(std::string(f) + "(" + composed + ")" + index, jet);
      const ex by_definition = parse_expression(std::string(f) + "(" + literal + ")" + index, jet);
      CHECK(same_numerically(closed, by_definition, jet));
    }
  // Transposes: ω(Rᵀ) = −Ω(R).
  CHECK(same_numerically(parse_expression("omega(transpose(" + composed + "))[2]", jet),
                         -parse_expression("omega_body(" + composed + ")[2]", jet), jet));
  CHECK(same_numerically(parse_expression("omega(transpose(" + literal + "))[3]", jet),
                         -parse_expression("omega_body(" + literal + ")[3]", jet), jet));
  // Elementary: ω(rotz(x)) = x' e_z.
  CHECK(same(parse_expression("omega(rotz(x))[3]", jet), jet.q(0, 1)));
  // Not rotations.
  CHECK_THROWS_AS(parse_expression("omega([[1, x, 0], [0, 1, 0], [0, 0, 1]])[1]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("omega(2*rotx(x))[1]", jet), nhc::ExpressionSyntaxError);
}

namespace {

nhc::Scene scene_with(const std::string& extra, const std::string& lagrangian = "T") {
  return nhc::parse_scene(
      "name = \"s\"\ncoordinates = [\"x\", \"y\", \"th\"]\nlagrangian = \"" + lagrangian + "\"\n" + extra, "defs.toml");
}

}  // namespace

TEST_CASE("quat(q0, q1, q2, q3) is the rotation of a unit quaternion with its angular velocities",
          "[scene][definitions][quat]") {
  const JetSpace jet = make_jet();
  // A unit quaternion for every x, y, z (Hopf-like angles over the whole 3-sphere), so that the
  // closed forms, which hold where |q| = 1, can be compared with R' R^T entry by entry.
  const std::string unit = "cos(x), sin(x)*cos(y), sin(x)*sin(y)*cos(z), sin(x)*sin(y)*sin(z)";
  const nhc::Value r = parse_value("quat(" + unit + ")", jet);
  REQUIRE(r.is_square3());
  // R R^T = I and det R = 1.
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) {
      ex rrt = 0;
      for (unsigned k = 0; k < 3; ++k) rrt += r.at(i, k) * r.at(j, k);
      CHECK(same_numerically(rrt, i == j ? 1 : 0, jet));
    }
  const ex det = r.at(0, 0) * (r.at(1, 1) * r.at(2, 2) - r.at(1, 2) * r.at(2, 1)) -
                 r.at(0, 1) * (r.at(1, 0) * r.at(2, 2) - r.at(1, 2) * r.at(2, 0)) +
                 r.at(0, 2) * (r.at(1, 0) * r.at(2, 1) - r.at(1, 1) * r.at(2, 0));
  CHECK(same_numerically(det, 1, jet));
  // omega and omega_body against the skew parts of R' R^T and R^T R', differentiated here.
  const nhc::Value dr = nhc::total_derivative(r, jet, 1);
  const auto product = [](const nhc::Value& a, bool a_transposed, const nhc::Value& b, bool b_transposed, unsigned i,
                          unsigned j) {
    ex sum = 0;
    for (unsigned k = 0; k < 3; ++k)
      sum += (a_transposed ? a.at(k, i) : a.at(i, k)) * (b_transposed ? b.at(j, k) : b.at(k, j));
    return sum;
  };
  const ex w[3] = {product(dr, false, r, true, 2, 1), product(dr, false, r, true, 0, 2),
                   product(dr, false, r, true, 1, 0)};
  const ex body[3] = {product(r, true, dr, false, 2, 1), product(r, true, dr, false, 0, 2),
                      product(r, true, dr, false, 1, 0)};
  for (int k = 0; k < 3; ++k) {
    const std::string index = "[" + std::to_string(k + 1) + "]";
    CHECK(same_numerically(parse_expression("omega(quat(" + unit + "))" + index, jet), w[k], jet));
    CHECK(same_numerically(parse_expression("omega_body(quat(" + unit + "))" + index, jet), body[k], jet));
    // Composed with an elementary rotation, by the rules of products (value.hpp).
    CHECK(same_numerically(parse_expression("omega(rotz(y)*quat(" + unit + "))" + index, jet),
                           parse_expression("omega(rotz(y))" + index, jet) +
                               parse_expression("(rotz(y)*omega(quat(" + unit + ")))" + index, jet),
                           jet));
  }
  // A half-angle quaternion about an axis is that axis' rotation.
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) {
      const std::string entry = "[" + std::to_string(i + 1) + ", " + std::to_string(j + 1) + "]";
      CHECK(same_numerically(parse_expression("quat(cos(x/2), sin(x/2), 0, 0)" + entry, jet),
                             parse_expression("rotx(x)" + entry, jet), jet));
      CHECK(same_numerically(parse_expression("quat(cos(y/2), 0, 0, sin(y/2))" + entry, jet),
                             parse_expression("rotz(y)" + entry, jet), jet));
    }
  CHECK_THROWS_AS(parse_expression("quat(x, y, z)[1, 1]", jet), nhc::ExpressionSyntaxError);
  CHECK_THROWS_AS(parse_expression("quat(x, y, z, [x, y])[1, 1]", jet), nhc::ExpressionSyntaxError);
}

TEST_CASE("omega() of three elementary rotations about coordinates keeps their Euler angles",
          "[scene][definitions][euler]") {
  struct Case {
    std::string rotation, axes;
    std::vector<std::string> angles;
    bool proper;  // sin of the middle angle (proper Euler angles), else cos (Tait-Bryan)
  };
  const std::vector<Case> recognised = {
      {"rotz(x)*rotx(y)*rotz(th)", "z-x-z", {"x", "y", "th"}, true},
      {"rotx(x)*roty(y)*rotx(th)", "x-y-x", {"x", "y", "th"}, true},
      {"rotz(x)*roty(y)*rotx(th)", "z-y-x", {"x", "y", "th"}, false},
      {"rotx(th)*rotz(x)*roty(y)", "x-z-y", {"th", "x", "y"}, false},
      // A transpose reverses the chain (angles negated); rotations by no coordinate before or after
      // it do not change the rank of the rates' map.
      {"transpose(rotz(x)*rotx(y)*rotz(th))", "z-x-z", {"th", "y", "x"}, true},
      {"rotx(1/3)*rotz(x)*rotx(y)*roty(th)*rotz(m*t)", "z-x-y", {"x", "y", "th"}, false},
  };
  for (const Case& c : recognised) {
    INFO(c.rotation);
    const nhc::Scene s = scene_with(
        "[parameters]\nm = 1.0\n[definitions]\nR = \"" + c.rotation + "\"\nw = \"omega(R)\"\n", "dot(w, w)/2");
    REQUIRE(s.euler_chains.size() == 1);
    const nhc::EulerChain& chain = s.euler_chains[0];
    CHECK(chain.axes == c.axes);
    CHECK(chain.angles == c.angles);
    CHECK(chain.zeros == (c.proper ? "0, pi" : "-pi/2, pi/2"));
    // The determinant of the rates' map, differentiated here from omega()'s ω (checked against
    // R' R^T above), is ± the recorded one at sample points.
    const JetSpace& jet = *s.jet;
    const nhc::Value w = parse_value("omega(" + c.rotation + ")", jet);
    GiNaC::matrix a(3, 3);
    for (unsigned i = 0; i < 3; ++i)
      for (unsigned j = 0; j < 3; ++j)
        a(i, j) = w.entries[i].diff(GiNaC::ex_to<GiNaC::symbol>(jet.q(*jet.coordinate_index(chain.angles[j]), 1)));
    const ex determinant = a.determinant();
    for (const double at : {0.3, 1.1, 2.6}) {
      GiNaC::exmap point;
      for (int i = 0; i < 3; ++i) point[jet.q(i, 0)] = at + 0.4 * i;
      point[jet.time()] = 0.7;
      point[jet.parameter(0)] = 1.0;
      const double expected = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(chain.determinant.subs(point))).to_double();
      const double got = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(determinant.subs(point))).to_double();
      CHECK(std::abs(std::abs(got) - std::abs(expected)) < 1e-12);
      CHECK(std::abs(expected) > 1e-3);
    }
  }
  // Not Euler angles: two rotations, an axis repeated next to itself, a coordinate twice, an angle
  // that is not a coordinate, a constant rotation inside the chain, a quaternion.
  for (const std::string rotation :
       {"rotz(x)*rotx(y)", "rotz(x)*rotz(y)*rotx(th)", "rotz(x)*rotx(y)*rotz(x)", "rotz(x)*rotx(y + th)*rotz(th)",
        "rotz(x)*rotx(y)*roty(1/3)*rotz(th)", "quat(cos(x), sin(x), 0, 0)*rotx(y)*rotz(th)"}) {
    INFO(rotation);
    CHECK(scene_with("[definitions]\nR = \"" + rotation + "\"\nw = \"omega_body(R)\"\n", "dot(w, w)/2")
              .euler_chains.empty());
  }
  // omega and omega_body of one chain: one record.
  const nhc::Scene twice =
      scene_with("[definitions]\nR = \"rotz(x)*rotx(y)*rotz(th)\"\nw = \"omega(R)\"\nW = \"omega_body(R)\"\n",
                 "dot(w, w)/2 + dot(W, W)/2");
  CHECK(twice.euler_chains.size() == 1);
}

TEST_CASE("definitions: any order, derivatives by D, unused ones reported", "[scene][definitions]") {
  const nhc::Scene s = scene_with(
      "[parameters]\nm = 2.0\n[definitions]\nT = \"m/2*dot(v, v)\"\nv = \"c'\"\n"
      "c = \"[x + cos(th), y + sin(th)]\"\nunused = \"x\"\n");
  const JetSpace& jet = *s.jet;
  const ex x1 = jet.q(0, 1), y1 = jet.q(1, 1), th = jet.q(2, 0), th1 = jet.q(2, 1);
  const ex vx = x1 - GiNaC::sin(th) * th1, vy = y1 + GiNaC::cos(th) * th1;
  CHECK(same(s.lagrangian, jet.parameter(0) / 2 * (vx * vx + vy * vy)));
  REQUIRE(s.warnings.size() == 1);
  CHECK(s.warnings[0] == "defs.toml:10:11: warning: definition 'unused' is never used");
  // A definition used only by an unused one is unused too.
  CHECK(scene_with("[definitions]\nT = \"x'^2\"\na = \"b\"\nb = \"x\"\n").warnings.size() == 2);
  CHECK_THROWS_AS(scene_with("[definitions]\nT = \"a\"\na = \"T\"\n"), nhc::InputError);
}

TEST_CASE("[forces] enter every model's residual as + Q_i", "[scene][definitions][derive]") {
  const nhc::Scene s = scene_with(
      "constraints = [\"y' - x'*th\"]\ndependent = [\"y\"]\n[parameters]\nb = 0.5\n"
      "[forces]\nx = \"-b*x'\"\nth = \"-b*t\"\n",
      "(x'^2 + y'^2 + th'^2)/2");
  const JetSpace& jet = *s.jet;
  nhc::Scene without = s;
  without.forces.clear();
  const ex b = jet.parameter(0);
  for (nhc::ModelKind kind :
       {nhc::ModelKind::vakonomic, nhc::ModelKind::chetaev, nhc::ModelKind::holder, nhc::ModelKind::suslov}) {
    const auto with_forces = nhc::derive_model(s, kind);
    const auto plain = nhc::derive_model(without, kind);
    REQUIRE(with_forces.equations.size() == 3);
    CHECK(same(with_forces.equations[0] - plain.equations[0], -b * jet.q(0, 1)));
    CHECK(same(with_forces.equations[1] - plain.equations[1], 0));
    CHECK(same(with_forces.equations[2] - plain.equations[2], -b * jet.time()));
  }
}

TEST_CASE("a chain of 1024 bodies with one definition per body parses", "[scene][definitions]") {
  const int n = 1024;
  std::string coordinates, lagrangian, definitions;
  for (int i = 1; i <= n; ++i) {
    const std::string k = std::to_string(i);
    coordinates += std::string(i > 1 ? ", " : "") + "\"x" + k + "\", \"y" + k + "\"";
    lagrangian += std::string(i > 1 ? " + " : "") + "L" + k;
    definitions += "L" + k + " = \"m/2*dot(v" + k + ", v" + k + ") - k/2*(x" + k + "^2 + y" + k + "^2)\"\nv" + k +
                   " = \"[x" + k + "', y" + k + "']\"\n";
  }
  const std::string text = "name = \"chain\"\ncoordinates = [" + coordinates + "]\nlagrangian = \"" + lagrangian +
                           "\"\n[parameters]\nm = 1.0\nk = 1.0\n[definitions]\n" + definitions;
  const nhc::Scene s = nhc::parse_scene(text, "chain.toml");
  CHECK(s.coordinate_count() == 2 * n);
  CHECK(s.lagrangian.nops() >= static_cast<std::size_t>(n));
  CHECK(s.warnings.empty());
}

TEST_CASE("a prescribed motion through t: a bead on a turning rod, every model", "[scene][definitions][derive]") {
  // p = r (cos Wt, sin Wt): L = m/2 (r'^2 + W^2 r^2), so E_r(L) = m W^2 r - m r''.
  const nhc::Scene s = nhc::parse_scene(
      "name = \"rod\"\ncoordinates = [\"r\", \"z\"]\nlagrangian = \"m/2*dot(p', p')\"\n"
      "constraints = [\"z' - t*r'\"]\ndependent = [\"z\"]\n[parameters]\nm = 2.0\nW = 3.0\n"
      "[definitions]\np = \"[r*cos(W*t), r*sin(W*t), z]\"\n",
      "rod.toml");
  const JetSpace& jet = *s.jet;
  const ex m = jet.parameter(*jet.parameter_index("m")), W = jet.parameter(*jet.parameter_index("W"));
  const ex r = jet.q(0, 0), r2 = jet.q(0, 2), l = jet.lambda(0, 0);
  // chetaev: R_r = E_r(L) + λ ∂f/∂r' = m W² r − m r'' − λ t.
  CHECK(same_numerically(nhc::derive_model(s, nhc::ModelKind::chetaev).equations[0],
                         m * W * W * r - m * r2 - l * jet.time(), jet));
  for (nhc::ModelKind kind : {nhc::ModelKind::vakonomic, nhc::ModelKind::holder, nhc::ModelKind::suslov}) {
    const auto model = nhc::derive_model(s, kind);
    REQUIRE(model.applicable);
    CHECK(model.equations[0].has(W));
    // The multiplier terms carry t (∂f/∂r' = −t); suslov eliminates λ with μ = m z', and its
    // R_r = m W² r − m r'' + m z' is free of t once sin² + cos² = 1 is applied.
    if (kind != nhc::ModelKind::suslov) CHECK(model.equations[0].has(jet.time()));
  }
}

TEST_CASE("SceneBuilder writes [definitions] and [forces]", "[scene][definitions]") {
  const nhc::Scene s = nhc::SceneBuilder("cart")
                           .coordinates({"x", "y"})
                           .parameter("c", 0.5)
                           .definition("v", "[x', y']")
                           .lagrangian("dot(v, v)/2")
                           .force("x", "-c*x'")
                           .build();
  const JetSpace& jet = *s.jet;
  CHECK(same(s.forces[0], -jet.parameter(0) * jet.q(0, 1)));
  CHECK(same(s.forces[1], 0));
  CHECK(same(s.lagrangian, (jet.q(0, 1) * jet.q(0, 1) + jet.q(1, 1) * jet.q(1, 1)) / 2));
}

TEST_CASE("long chains of definitions resolve without deep recursion, deep nesting is refused",
          "[scene][definitions]") {
  // d_k = d_{k-1}, 5000 links: resolved leaves first (the recursive descent overflowed the
  // stack at about 2,400).
  // d1 … d4999 of a chain d_k = "d_{k-1}", after a head that sets T and d0.
  const auto chain_after = [](const std::string& head) {
    std::string text = "[definitions]\n" + head;
    for (int k = 1; k < 5000; ++k) text += "d" + std::to_string(k) + " = \"d" + std::to_string(k - 1) + "\"\n";
    return text;
  };
  const nhc::Scene s = scene_with(chain_after("T = \"d4999^2\"\nd0 = \"x'\"\n"));
  CHECK(same(s.lagrangian, GiNaC::pow(s.jet->q(0, 1), 2)));
  CHECK(s.warnings.empty());
  // The same chain closed into a cycle: named by its ends, on one line.
  try {
    scene_with(chain_after("T = \"d4999\"\nd0 = \"d4999 + x\"\n"));
    FAIL("a cycle was accepted");
  } catch (const nhc::InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("depends on itself (d4999 -> d4998 -> d4997 -> d4996 -> … (4992 more) -> "
                                         "d3 -> d2 -> d1 -> d0 -> d4999)"));
  }
  // sin(sin(…)) 40 deep: refused at the definition that passes 32.
  std::string nested = "[definitions]\nT = \"e39\"\ne0 = \"x'\"\n";
  for (int k = 1; k < 40; ++k) nested += "e" + std::to_string(k) + " = \"sin(e" + std::to_string(k - 1) + ")\"\n";
  try {
    scene_with(nested);
    FAIL("40-deep nesting was accepted");
  } catch (const nhc::InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("in definition 'e33' \"sin(e32)\": functions nested more than 32 deep"));
  }
}
