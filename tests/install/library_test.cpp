// [library]: the front end used from C++ (nhc::codegen): scenes built in code with SceneBuilder
// are validated like scene files and go through the same pipeline.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "nhc/codegen.hpp"

namespace {

/// examples/appell_hamel.toml, key by key.
nhc::SceneBuilder appell_hamel() {
  nhc::SceneBuilder b("appell_hamel");
  b.coordinates({"x", "y", "z"})
      .lagrangian("m/2*(x'^2 + y'^2 + z'^2) - m*g*z")
      .constraint("z' - b/a*sqrt(x'^2 + y'^2)")
      .dependent({"z"})
      .models({nhc::ModelKind::vakonomic, nhc::ModelKind::chetaev, nhc::ModelKind::holder, nhc::ModelKind::suslov})
      .parameter("m", 1.0)
      .parameter("g", 9.81)
      .parameter("a", 1.0)
      .parameter("b", 0.5)
      .initial_time(0.0)
      .initial("x", {0.0, 1.0})
      .initial("y", {0.0, 0.5})
      .initial("z", {0.0})
      .initial("lambda1", {0.0})
      .simulate(nhc::ModelKind::chetaev, 0.2, 1e-8, 1e-10)
      .invariant("energy", "m/2*(x'^2 + y'^2 + z'^2) + m*g*z");
  return b;
}

/// The header without its banner lines that name the scene file.
std::string without_file_lines(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.find(" from ") == std::string::npos && line.find("nhc generate ") == std::string::npos) out += line + "\n";
  return out;
}

std::string input_error_of(const nhc::SceneBuilder& builder) {
  try {
    builder.build();
  } catch (const nhc::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a scene built in code equals the scene file it spells out", "[library]") {
  const nhc::Scene built = appell_hamel().build();
  const nhc::Scene loaded = nhc::load_scene(NHC_SOURCE_DIR "/examples/appell_hamel.toml");
  CHECK(built.source_path.empty());
  CHECK(built.name == loaded.name);
  CHECK(built.jet->coordinates() == loaded.jet->coordinates());
  CHECK(built.jet->parameters() == loaded.jet->parameters());
  CHECK(built.parameter_values == loaded.parameter_values);
  CHECK(built.models == loaded.models);
  CHECK(built.dependent == loaded.dependent);
  CHECK(built.initial.values == loaded.initial.values);
  CHECK(built.simulate.t_end == loaded.simulate.t_end);

  // The whole pipeline gives the same code: derivation, reduction, CSE and printing are
  // deterministic (docs/generated-code.md), so equal headers mean equal equations.
  for (nhc::ModelKind kind : {nhc::ModelKind::chetaev, nhc::ModelKind::vakonomic}) {
    const auto header_of = [kind](const nhc::Scene& scene) {
      const nhc::Index1System system = nhc::reduce_to_index1(scene, nhc::derive_model(scene, kind));
      return nhc::generate_header(scene, system, {nhc::JacobianKind::dense});
    };
    const nhc::GeneratedHeader from_code = header_of(built), from_file = header_of(loaded);
    CHECK(from_code.file_name == from_file.file_name);
    CHECK(from_code.text.find("from a scene built in code") != std::string::npos);
    CHECK(without_file_lines(from_code.text) == without_file_lines(from_file.text));
  }
}

TEST_CASE("toml() is a scene file: numbers and strings read back exactly", "[library]") {
  nhc::SceneBuilder b("tricky");
  b.coordinates({"x", "y"})
      .parameter("c", 0.1)
      .parameter("e", 1e-300)
      .parameter("big", 123456789.0)
      .lagrangian("c/2*x'^2 + e*y'^2 - big*y")
      .constraint("x' - y'");
  const nhc::Scene scene = nhc::parse_scene(b.toml(), "tricky.toml");
  // Parameters are in name order, as in a scene file.
  REQUIRE(scene.jet->parameters() == std::vector<std::string>{"big", "c", "e"});
  CHECK(scene.parameter_values == std::vector<double>{123456789.0, 0.1, 1e-300});
  CHECK(scene.models.size() == 4);
}

TEST_CASE("SceneBuilder reports errors as the scene loader does", "[library]") {
  SECTION("a bad expression names the builder and the text") {
    nhc::SceneBuilder b("bad");
    b.coordinates({"x", "y"}).lagrangian("x'^2/2 +").constraint("x' - y'");
    const std::string message = input_error_of(b);
    CHECK(message.find("bad (built in code):") == 0);
    CHECK(message.find("in lagrangian \"x'^2/2 +\"") != std::string::npos);
  }
  SECTION("a name that needs escaping is reported, not a TOML syntax error") {
    nhc::SceneBuilder b("no\"pe\n");
    b.coordinates({"x"}).lagrangian("x'^2/2");
    const std::string message = input_error_of(b);
    CHECK(message.find("invalid name") != std::string::npos);
    CHECK(message.find("TOML syntax") == std::string::npos);
  }
  SECTION("a parameter given twice") {
    nhc::SceneBuilder b("twice");
    b.coordinates({"x"}).parameter("m", 1).parameter("m", 2).lagrangian("m*x'^2/2");
    CHECK_FALSE(input_error_of(b).empty());
  }
  SECTION("an unknown initial variable and a non-finite parameter") {
    nhc::SceneBuilder b("init");
    b.coordinates({"x"}).lagrangian("x'^2/2").initial("w", {1.0});
    CHECK(input_error_of(b).find("[initial] names 'w'") != std::string::npos);
    nhc::SceneBuilder c("inf");
    c.coordinates({"x"}).parameter("m", std::numeric_limits<double>::infinity()).lagrangian("m*x'^2/2");
    CHECK(input_error_of(c).find("must be finite") != std::string::npos);
  }
}

TEST_CASE("derive, analyse and emit a scene built in code", "[library]") {
  // The particle of examples/particle.toml under q'·q'' = 0: Chetaev gives λ = 0.
  const nhc::Scene scene = nhc::SceneBuilder("particle")
                               .coordinates({"q1", "q2", "q3"})
                               .lagrangian("1/2*(q1'^2 + q2'^2 + q3'^2)")
                               .constraint("q1'*q1'' + q2'*q2'' + q3'*q3''")
                               .initial("q1", {0.0, 1.0})
                               .initial("q2", {0.0, 2.0})
                               .initial("q3", {0.0, 2.0})
                               .build();
  const nhc::DerivedModel chetaev = nhc::derive_model(scene, nhc::ModelKind::chetaev);
  REQUIRE(chetaev.applicable);
  const nhc::ModelAnalysis analysis = nhc::analyze_model(scene, chetaev);
  REQUIRE(analysis.ok());
  for (const nhc::InitialValue& v : analysis.initial->leading)
    if (v.name == "lambda1") CHECK(std::abs(v.value) < 1e-12);

  std::ostringstream latex, json;
  nhc::write_derivation_latex(latex, scene, {chetaev});
  nhc::write_analysis_json(json, scene, {analysis});
  CHECK(latex.str().find("\\begin{document}") != std::string::npos);
  CHECK(json.str().find("\"model\"") != std::string::npos);

  const nhc::GeneratedHeader header =
      nhc::generate_header(scene, nhc::reduce_to_index1(scene, chetaev), {nhc::JacobianKind::sparse});
  CHECK(header.file_name == "particle_chetaev.hpp");
  CHECK(header.text.find("inline constexpr int jacobian_nnz") != std::string::npos);
}
