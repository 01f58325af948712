// [visual] (scene_visual.hpp): every shape read with its values' kinds, TOML 1.1 inline tables
// over several lines, numbers, arrays and expressions of the scene's quantities (checked by
// evaluating them at a point, against the same quantity computed by hand).
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/scene/scene.hpp"

namespace {

const char* kScene = R"toml(name = "cart"
coordinates = ["x", "y", "psi"]
lagrangian = "x'^2 + y'^2 + psi'^2"
[parameters]
r = 0.25
[definitions]
R = "rotz(psi)"
p = "[x, y, r]"
[visual]
ball  = { shape = "sphere", radius = "r", center = "p", rotation = "R" }
wheel = { shape = "cylinder", radius = "2*r", length = 0.03,
          center = "p + R*[1, 0, 0]", rotation = "R*roty(x)",
          axis = "y", color = "#3af" }
frame = { shape = "box", size = [0.5, "r", 0.04], center = "[x, y, 0]", opacity = 0.5 }
rod   = { shape = "segment", from = "p", to = "[0, 0, 0]" }
path  = { shape = "trace", point = "[x, y, 0]" }
ground = { shape = "plane" }
)toml";

/// e (definitions substituted) at x = 0.3, y = -0.2, psi = 0.7 and the parameters.
double at_point(const nhc::Scene& scene, const GiNaC::ex& e) {
  GiNaC::exmap point = scene.parameter_substitution();
  point[scene.jet->q(0, 0)] = 0.3;
  point[scene.jet->q(1, 0)] = -0.2;
  point[scene.jet->q(2, 0)] = 0.7;
  return GiNaC::ex_to<GiNaC::numeric>(nhc::expand_intermediates(e).subs(point).evalf()).to_double();
}

}  // namespace

TEST_CASE("visual: the six shapes, over several lines, with their values", "[scene][visual]") {
  const nhc::Scene scene = nhc::parse_scene(kScene, "cart.toml");
  REQUIRE(scene.visuals.size() == 6);
  const nhc::SceneVisual& ball = scene.visuals[0];
  CHECK(ball.name == "ball");
  CHECK(ball.shape == nhc::VisualShape::sphere);
  CHECK(at_point(scene, ball.values.at("radius").entries[0]) == Approx(0.25));
  CHECK(at_point(scene, ball.values.at("center").entries[2]) == Approx(0.25));
  const nhc::SceneVisual& wheel = scene.visuals[1];
  CHECK(wheel.shape == nhc::VisualShape::cylinder);
  CHECK(wheel.axis == 1);
  CHECK(wheel.color == "#33aaff");
  // center = p + rotz(psi) e_x: x + cos(psi), y + sin(psi), r.
  CHECK(at_point(scene, wheel.values.at("center").entries[0]) == Approx(0.3 + std::cos(0.7)));
  CHECK(at_point(scene, wheel.values.at("center").entries[1]) == Approx(-0.2 + std::sin(0.7)));
  // rotation = rotz(psi) roty(x): entry (3, 1) is -sin(x).
  CHECK(at_point(scene, wheel.values.at("rotation").entries[6]) == Approx(-std::sin(0.3)));
  CHECK(wheel.where.line == 11);
  const nhc::SceneVisual& frame = scene.visuals[2];
  CHECK(at_point(scene, frame.values.at("size").entries[1]) == Approx(0.25));
  CHECK(frame.opacity == 0.5);
  CHECK(frame.values.count("rotation") == 0);
  CHECK(scene.visuals[3].shape == nhc::VisualShape::segment);
  CHECK(scene.visuals[4].shape == nhc::VisualShape::trace);
  CHECK(scene.visuals[5].shape == nhc::VisualShape::plane);
  CHECK(scene.warnings.empty());  // R and p are used by [visual] only: not "never used"
}

TEST_CASE("visual: [visual] does not change the equations' source (the scene cache)", "[scene][visual]") {
  const std::string without = std::string(kScene).substr(0, std::string(kScene).find("[visual]"));
  CHECK(nhc::equations_source(kScene) == nhc::equations_source(without));
}
