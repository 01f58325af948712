// Generated code cannot be steered by a scene. Scene text (names, the scene file's name) reaches a
// generated header only inside `//` comments, sanitised so that it cannot close them or continue
// them onto the next line, and inside string literals, escaped; the only identifier taken from a
// scene is its validated name. Checked with hostile text of every kind: comment closers,
// newlines, carriage returns, backslash-newline, trigraphs (`??/` splices lines where trigraphs
// are processed), quotes, Unicode line separators and invalid UTF-8. Each header must compile
// with warnings as errors, with and without trigraph processing, and the marker EVIL of every
// payload must not occur outside comments and string literals.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"

namespace fs = std::filesystem;

namespace {

/// Every way a text could leave a `//` comment or a string literal, each with the marker EVIL.
const std::vector<std::string> kPayloads = {
    "a */ EVIL_closer /* b",
    "a\nEVIL_newline();",
    "a\r\nEVIL_crlf();",
    "a\rEVIL_cr();",
    "a\\\nEVIL_splice();",
    "a\\",  // a backslash at the very end of the comment line
    "a ?\?/\nEVIL_trigraph();",
    "a ?\?/",
    "a \xff\xff/\nEVIL_invalid_utf8();",
    "a\xe2\x80\xa8 EVIL_line_separator();",
    "a\xe2\x80\xa9 EVIL_paragraph_separator();",
    "a\xc2\x85 EVIL_next_line();",
    "a\" EVIL_quote \"",
    "a' EVIL_apostrophe '",
    "R\"(EVIL_raw)\"",
    "#include <EVIL_include>",
    "\f\v\x01\x7f EVIL_control",
};

/// The header with comments removed and string and character literals emptied, by the rules of
/// translation phases 1-3 for a text that has no trigraphs and no backslash-newline (asserted
/// separately).
std::string code_outside_comments_and_literals(const std::string& h) {
  std::string out;
  std::size_t i = 0;
  while (i < h.size()) {
    if (h.compare(i, 2, "//") == 0) {
      while (i < h.size() && h[i] != '\n') ++i;
      out += ' ';
    } else if (h.compare(i, 2, "/*") == 0) {
      const std::size_t end = h.find("*/", i + 2);
      i = end == std::string::npos ? h.size() : end + 2;
      out += ' ';
    } else if (h[i] == '"' || h[i] == '\'') {
      const char quote = h[i++];
      while (i < h.size() && h[i] != quote && h[i] != '\n') i += h[i] == '\\' ? 2 : 1;
      ++i;
      out += quote;
      out += quote;
    } else {
      out += h[i++];
    }
  }
  return out;
}

void check_confined(const std::string& header) {
  CHECK(header.find("??") == std::string::npos);
  CHECK(header.find("\\\n") == std::string::npos);
  CHECK(header.find('\r') == std::string::npos);
  for (const char c : header) {
    const auto u = static_cast<unsigned char>(c);
    INFO("byte " << static_cast<int>(u));
    CHECK((u == '\n' || (u >= 0x20 && u < 0x7f)));
  }
  const std::string code = code_outside_comments_and_literals(header);
  INFO(code);
  CHECK(code.find("EVIL") == std::string::npos);
  CHECK(header.find("EVIL") != std::string::npos);  // the payloads did reach the header
}

/// Compiles a translation unit that includes the header, warnings as errors, with `extra` flags.
void check_compiles(const fs::path& header, const std::string& extra) {
  const fs::path source = header.string() + ".cpp", log = header.string() + ".log";
  std::ofstream(source) << "#include \"" << header.filename().string() << "\"\n";
  const std::string command =
      std::string("'") + NHC_CXX_COMPILER + "' -std=c++17 -Wall -Wextra -Werror -fsyntax-only " + extra + " -I'" +
      header.parent_path().string() + "' '" + source.string() + "' >'" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log);
  std::ostringstream messages;
  messages << in.rdbuf();
  INFO(command << "\n" << messages.str());
  CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 0));
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(NHC_BINARY_DIR) / "tests" / "codegen" / "scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// A scene built in code, skipping the loader's validation: every name is hostile.
nhc::Scene hostile_scene(const std::string& name, const std::string& source_path) {
  nhc::Scene scene;
  scene.name = name;
  scene.source_path = source_path;
  const std::vector<std::string> coordinates = {kPayloads[0], kPayloads[1], kPayloads[4]};
  std::vector<std::string> parameters;  // the other payloads: names stay distinct
  for (std::size_t k = 2; k < kPayloads.size(); ++k)
    if (k != 4) parameters.push_back(kPayloads[k]);
  scene.jet = std::make_shared<nhc::JetSpace>(coordinates, 1, parameters);
  const nhc::JetSpace& jet = *scene.jet;
  GiNaC::ex kinetic = 0, potential = 0;
  for (int i = 0; i < 3; ++i) kinetic += GiNaC::pow(jet.q(i, 1), 2) / 2;
  for (int p = 0; p < static_cast<int>(parameters.size()); ++p) {
    scene.parameter_values.push_back(1.0 + p);
    potential += jet.parameter(p) * jet.q(p % 3, 0);
  }
  scene.lagrangian = kinetic - potential;
  scene.constraints = {jet.q(2, 1) - jet.q(0, 0) * jet.q(1, 1)};
  scene.constraint_texts = {kPayloads[2]};
  scene.dependent = {2};
  scene.models = {nhc::ModelKind::chetaev};
  scene.reference.all = {{0, jet.time()}};
  scene.invariants = {{kPayloads[6], kinetic, {}}, {kPayloads[8], kinetic + potential, {}}};
  return scene;
}

nhc::GeneratedHeader generate(const nhc::Scene& scene, nhc::JacobianKind jacobian) {
  const nhc::Index1System system = nhc::reduce_to_index1(scene, nhc::derive_model(scene, nhc::ModelKind::chetaev));
  nhc::HeaderOptions options;
  options.jacobian = jacobian;
  return nhc::generate_header(scene, system, options);
}

}  // namespace

TEST_CASE("sanitised comments cannot be closed, continued or turned into trigraphs", "[codegen][hostile]") {
  for (const std::string& payload : kPayloads) {
    INFO(payload);
    const std::string s = nhc::sanitize_comment(payload);
    CHECK(s.find('\n') == std::string::npos);
    CHECK(s.find('\r') == std::string::npos);
    CHECK(s.find('\\') == std::string::npos);
    CHECK(s.find("*/") == std::string::npos);
    CHECK(s.find("??") == std::string::npos);
    for (const char c : s) CHECK((static_cast<unsigned char>(c) >= 0x20 && static_cast<unsigned char>(c) < 0x7f));
  }
  // Replacement characters cannot form a sequence either.
  CHECK(nhc::sanitize_comment("\xff\xff/") == "? ?/");
  CHECK(nhc::sanitize_comment("*\xff/") == "*?/");
  CHECK(nhc::sanitize_comment("**/") == "** /");
  for (const std::string& payload : kPayloads) {
    const std::string literal = nhc::cpp_string_literal(payload);
    INFO(literal);
    CHECK(code_outside_comments_and_literals(literal) == "\"\"");
    CHECK(literal.find('?') == std::string::npos);
  }
}

TEST_CASE("hostile names and file names stay in comments and literals of a compiling header", "[codegen][hostile]") {
  const fs::path dir = scratch("hostile_in_code");
  // The banner names the scene file without its directory: hostile text after the last slash.
  std::string source_path = "scenes/";
  for (const std::string& payload : kPayloads)
    if (payload.find('/') == std::string::npos && payload.find('\\') == std::string::npos) source_path += payload + " ";
  source_path += ".toml";
  const nhc::Scene scene = hostile_scene("hostile", source_path);
  for (const nhc::JacobianKind jacobian :
       {nhc::JacobianKind::dense, nhc::JacobianKind::sparse, nhc::JacobianKind::none}) {
    INFO("jacobian " << nhc::to_string(jacobian));
    const nhc::GeneratedHeader header = generate(scene, jacobian);
    CHECK(header.file_name == "hostile_chetaev.hpp");
    check_confined(header.text);
    const fs::path path = dir / (nhc::to_string(jacobian) + "_" + header.file_name);
    std::ofstream(path, std::ios::binary) << header.text;
    check_compiles(path, "");
    check_compiles(path, "-trigraphs");
    check_compiles(path, "-DNHC_EXPORT_MODEL_TABLE");
  }
}

TEST_CASE("a scene name that is not an identifier never reaches the header", "[codegen][hostile]") {
  for (const std::string& name : {std::string("a/b"), std::string("../x"), std::string("x y"), std::string("int"),
                                  std::string(""), std::string("x;y"), std::string("x\ny"), kPayloads[0]}) {
    INFO(name);
    nhc::Scene scene = hostile_scene("ok", "s.toml");
    scene.name = name;
    CHECK_THROWS_AS(generate(scene, nhc::JacobianKind::dense), nhc::InputError);
  }
}

TEST_CASE("nhc generate on a scene file with a hostile file name", "[codegen][hostile]") {
  const fs::path dir = scratch("hostile_file_name");
  const std::string scene_text = nhc::test::read_file(std::string(NHC_SOURCE_DIR) + "/examples/particle.toml");
  REQUIRE(!scene_text.empty());
  // Every payload that can be part of a file name (no slash, no NUL).
  std::string file_name;
  for (const std::string& payload : kPayloads)
    if (payload.find('/') == std::string::npos) file_name += payload + " ";
  file_name += ".toml";
  const fs::path scene = dir / file_name;
  std::ofstream(scene, std::ios::binary) << scene_text;
  REQUIRE(fs::exists(scene));
  const fs::path out = dir / "out";
  // The path goes through the shell as an argument: single quotes, with ' escaped.
  std::string quoted = "'";
  for (const char c : scene.string()) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  quoted += "'";
  const nhc::test::Run r = nhc::test::run(
      nhc::test::nhc_command() + " generate " + quoted + " --quiet -o '" + out.string() + "'", dir.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const fs::path header = out / "particle_chetaev.hpp";
  const std::string text = nhc::test::read_file(header.string());
  REQUIRE(!text.empty());
  check_confined(text);
  check_compiles(header, "");
  check_compiles(header, "-trigraphs");
}
