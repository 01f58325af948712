// `nhc derive` through the real binary: the malformed-input corpus (tests/bad/), the JSON
// schema of the issue with a symbolic round trip of every expression through nhc's own parser,
// and the LaTeX output compiled by pdflatex.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <dirent.h>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/expr/zero_test.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene.hpp"
#include "command_runner.hpp"

namespace {

// ---- running the binary -------------------------------------------------------------------

using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::Run;
using nhc::test::run;
using nhc::test::scratch_dir;

std::vector<std::string> list_dir(const std::string& dir, const std::string& suffix) {
  std::vector<std::string> names;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > suffix.size() && n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0)
        names.push_back(n);
    }
    ::closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// ---- a tiny JSON reader -------------------------------------------------------------------

struct Json {
  enum Kind { null, boolean, number, string, array, object } kind = null;
  bool b = false;
  double n = 0;
  std::string s;
  std::vector<Json> items;
  std::vector<std::pair<std::string, Json>> members;  // in document order

  const Json* get(const std::string& key) const {
    for (const auto& [k, v] : members)
      if (k == key) return &v;
    return nullptr;
  }
};

class JsonReader {
 public:
  explicit JsonReader(const std::string& text) : t_(text) {}
  Json document() {
    Json v = value();
    space();
    if (i_ != t_.size()) throw std::runtime_error("JSON: trailing text at " + std::to_string(i_));
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(i_));
  }
  void space() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\n' || t_[i_] == '\t' || t_[i_] == '\r')) ++i_;
  }
  bool take(char c) {
    space();
    if (i_ < t_.size() && t_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!take(c)) fail(std::string("expected '") + c + "'");
  }
  std::string str() {
    expect('"');
    std::string out;
    while (i_ < t_.size() && t_[i_] != '"') {
      char c = t_[i_++];
      if (static_cast<unsigned char>(c) < 0x20) fail("control character in string");
      if (c == '\\') {
        if (i_ >= t_.size()) fail("dangling escape");
        const char e = t_[i_++];
        switch (e) {
          case '"':
            out += '"';
            break;
          case '\\':
            out += '\\';
            break;
          case '/':
            out += '/';
            break;
          case 'b':
            out += '\b';
            break;
          case 'f':
            out += '\f';
            break;
          case 'n':
            out += '\n';
            break;
          case 'r':
            out += '\r';
            break;
          case 't':
            out += '\t';
            break;
          case 'u': {
            if (i_ + 4 > t_.size()) fail("short \\u escape");
            const unsigned cp = std::stoul(t_.substr(i_, 4), nullptr, 16);
            i_ += 4;
            if (cp < 0x80) out += static_cast<char>(cp);
            else if (cp < 0x800) {
              out += static_cast<char>(0xC0 | (cp >> 6));
              out += static_cast<char>(0x80 | (cp & 0x3F));
            } else {
              out += static_cast<char>(0xE0 | (cp >> 12));
              out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
              out += static_cast<char>(0x80 | (cp & 0x3F));
            }
            break;
          }
          default:
            fail("bad escape");
        }
      } else {
        out += c;
      }
    }
    expect('"');
    return out;
  }
  Json value() {
    space();
    if (i_ >= t_.size()) fail("unexpected end");
    Json v;
    const char c = t_[i_];
    if (c == '{') {
      ++i_;
      v.kind = Json::object;
      if (take('}')) return v;
      do {
        space();
        std::string k = str();
        expect(':');
        v.members.emplace_back(k, value());
      } while (take(','));
      expect('}');
    } else if (c == '[') {
      ++i_;
      v.kind = Json::array;
      if (take(']')) return v;
      do v.items.push_back(value());
      while (take(','));
      expect(']');
    } else if (c == '"') {
      v.kind = Json::string;
      v.s = str();
    } else if (t_.compare(i_, 4, "true") == 0) {
      i_ += 4;
      v.kind = Json::boolean;
      v.b = true;
    } else if (t_.compare(i_, 5, "false") == 0) {
      i_ += 5;
      v.kind = Json::boolean;
    } else if (t_.compare(i_, 4, "null") == 0) {
      i_ += 4;
    } else {
      std::size_t used = 0;
      v.kind = Json::number;
      v.n = std::stod(t_.substr(i_), &used);
      if (used == 0) fail("bad value");
      i_ += used;
    }
    return v;
  }
  const std::string& t_;
  std::size_t i_ = 0;
};

bool same(const GiNaC::ex& a, const GiNaC::ex& b) {
  const GiNaC::ex d = (a - b).expand();
  return d.is_zero() || d.normal().is_zero();
}

std::string example(const std::string& name) { return std::string(NHC_SOURCE_DIR) + "/examples/" + name + ".toml"; }

}  // namespace

TEST_CASE("malformed scenes: exit 2, one located error line, no output file", "[cli][bad]") {
  const std::string bad_dir = std::string(NHC_SOURCE_DIR) + "/tests/bad";
  const std::vector<std::string> cases = list_dir(bad_dir, ".toml");
  REQUIRE(cases.size() >= 30);
  const std::string dir = scratch_dir("bad");
  const std::regex expect_line(R"(^#\s*expect:\s*(\d+):(\d+)\s*$)");
  for (const std::string& name : cases) {
    INFO("case " << name);
    const std::string path = bad_dir + "/" + name;
    const std::string text = read_file(path);
    const std::string first = text.substr(0, text.find('\n'));
    std::smatch m;
    REQUIRE(std::regex_match(first, m, expect_line));
    const std::string where = path + ":" + m[1].str() + ":" + m[2].str() + ": error: ";
    const std::string output = dir + "/" + name + ".out";
    const Run r = run(nhc_command() + " derive '" + path + "' --format json -o '" + output + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    INFO("stderr: " << r.err);
    REQUIRE(!r.err.empty());
    CHECK(r.err.back() == '\n');
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.rfind(where, 0) == 0);
    CHECK(r.err.size() > where.size() + 1);  // a message follows
    CHECK(!file_exists(output));
    // No temporary left behind either.
    for (const auto& leftover : list_dir(dir, "")) CHECK(leftover.find(name) == std::string::npos);
  }
}

TEST_CASE("a missing scene file and bad flags exit 2", "[cli][bad]") {
  const std::string dir = scratch_dir("flags");
  Run r = run(nhc_command() + " derive '" + dir + "/nonexistent.toml'", dir);
  CHECK(r.exit_code == 2);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  r = run(nhc_command() + " derive '" + example("particle") + "' --format yaml", dir);
  CHECK(r.exit_code == 2);
  r = run(nhc_command() + " derive '" + example("particle") + "' --model lagrange", dir);
  CHECK(r.exit_code == 2);
}

TEST_CASE("generate --print-file-name names the file generate writes, and writes nothing", "[cli]") {
  // nhc_add_model's OUT_VAR asks this instead of reading the scene (cmake/nhcFunctions.cmake).
  for (const std::string model : {"", "vakonomic"}) {
    const std::string dir = scratch_dir("print-file-name-" + (model.empty() ? std::string("default") : model));
    const std::string model_flag = model.empty() ? "" : " --model " + model;
    const Run printed = run(nhc_command() + " generate '" + example("appell_hamel") + "'" + model_flag +
                                " --print-file-name -o '" + dir + "/out'",
                            dir);
    REQUIRE(printed.exit_code == 0);
    CHECK(list_dir(dir + "/out", ".hpp").empty());
    const Run written = run(
        nhc_command() + " generate '" + example("appell_hamel") + "'" + model_flag + " --quiet -o '" + dir + "/out'",
        dir);
    REQUIRE(written.exit_code == 0);
    const std::vector<std::string> files = list_dir(dir + "/out", ".hpp");
    REQUIRE(files.size() == 1);
    CHECK(printed.out == files[0] + "\n");
  }
}

TEST_CASE("JSON output: schema, symbols, and a symbolic round trip", "[cli][json]") {
  for (const char* name : {"particle", "appell_hamel"}) {
    INFO("scene " << name);
    const std::string dir = scratch_dir(std::string("json_") + name);
    const std::string output = dir + "/out.json";
    const Run r = run(nhc_command() + " derive '" + example(name) + "' --format json -o '" + output + "'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.err.empty());
    const Json doc = JsonReader(read_file(output)).document();

    // Independent path: the same scene loaded and derived in-process.
    const nhc::Scene scene = nhc::load_scene(example(name));
    const nhc::JetSpace& jet = *scene.jet;

    REQUIRE(doc.kind == Json::object);
    REQUIRE(doc.get("scene"));
    CHECK(doc.get("scene")->s == scene.name);
    const Json* params = doc.get("parameters");
    REQUIRE(params);
    REQUIRE(params->kind == Json::array);
    CHECK(params->items.size() == jet.parameters().size());
    for (const Json& p : params->items) CHECK(jet.parameter_index(p.s).has_value());

    const Json* symbols = doc.get("symbols");
    REQUIRE(symbols);
    REQUIRE(symbols->kind == Json::object);
    std::map<std::string, std::pair<std::string, int>> listed;
    for (const auto& [printed, info] : symbols->members) {
      REQUIRE(info.get("of"));
      REQUIRE(info.get("order"));
      CHECK(info.get("order")->kind == Json::number);
      listed[printed] = {info.get("of")->s, static_cast<int>(info.get("order")->n)};
      CHECK(printed == nhc::jet_symbol_name(info.get("of")->s, static_cast<int>(info.get("order")->n)));
    }

    const Json* models = doc.get("models");
    REQUIRE(models);
    REQUIRE(models->kind == Json::object);
    CHECK(models->members.size() == scene.models.size());
    nhc::ExpressionRules read_back;
    read_back.allow_multipliers = true;
    for (const auto& [model_name, model] : models->members) {
      INFO("model " << model_name);
      const auto kind = nhc::parse_model_kind(model_name);
      REQUIRE(kind.has_value());
      const nhc::DerivedModel expected = nhc::derive_model(scene, *kind);
      REQUIRE(model.get("applicable"));
      REQUIRE(model.get("applicable")->kind == Json::boolean);
      CHECK(model.get("applicable")->b == expected.applicable);
      if (!model.get("applicable")->b) {
        REQUIRE(model.get("reason"));
        CHECK(!model.get("reason")->s.empty());
        continue;
      }
      const Json* equations = model.get("equations");
      REQUIRE(equations);
      REQUIRE(equations->items.size() == static_cast<std::size_t>(scene.coordinate_count()));
      // The constraints are equations for three models and monitored for suslov.
      const Json* constraints = model.get("constraints");
      REQUIRE(constraints);
      REQUIRE(model.get("constraints_solved"));
      CHECK(model.get("constraints_solved")->b == expected.constraints_are_equations);
      REQUIRE(constraints->items.size() == static_cast<std::size_t>(scene.constraint_count()));
      const Json* multipliers = model.get("multipliers");
      REQUIRE(multipliers);
      REQUIRE(multipliers->items.size() == expected.multipliers.size());
      for (std::size_t a = 0; a < expected.multipliers.size(); ++a)
        CHECK(multipliers->items[a].s == expected.multipliers[a]);

      auto check_expression = [&](const std::string& text, const GiNaC::ex& reference) {
        INFO("expression " << text);
        const GiNaC::ex parsed = nhc::parse_expression(text, jet, read_back);
        CHECK(same(parsed, reference));
        // Every jet symbol in it is listed, with the right variable and order.
        for (const auto& c : jet.jet_coordinates_in(parsed)) {
          const std::string of = jet.variable_name(c.kind, c.index);
          const std::string printed = nhc::jet_symbol_name(of, c.order);
          INFO("symbol " << printed);
          REQUIRE(listed.count(printed) == 1);
          CHECK(listed[printed].first == of);
          CHECK(listed[printed].second == c.order);
        }
      };
      for (std::size_t i = 0; i < equations->items.size(); ++i)
        check_expression(equations->items[i].s, expected.equations[i]);
      for (std::size_t a = 0; a < constraints->items.size(); ++a)
        check_expression(constraints->items[a].s, expected.constraints[a]);
    }
  }
}

TEST_CASE("definitions stay named: the JSON's \"definitions\" substituted give the --expand equations",
          "[cli][json][intermediates]") {
  // Two derivations of each example with definitions: by default through its definitions kept
  // as named quantities, listed after the equations; with --expand through every definition
  // substituted first. Substituting the listed definitions, last to first, into the
  // first gives functions equal to the second (compared at sample points: the two may differ
  // by sin² + cos² = 1).
  // The small examples' definitions are substituted where they are small (intermediate.hpp):
  // the rolling disk keeps its kinetic energy and slip velocity, the bicycle hundreds.
  for (const char* name : {"rolling_disk", "whipple/whipple_bicycle"}) {
    INFO("scene " << name);
    const std::string dir = scratch_dir("where");
    const Run kept = run(nhc_command() + " derive '" + example(name) + "' -m chetaev --format json", dir);
    const Run expanded = run(nhc_command() + " derive '" + example(name) + "' -m chetaev --format json --expand", dir);
    REQUIRE(kept.exit_code == 0);
    REQUIRE(expanded.exit_code == 0);
    const Json with_names = JsonReader(kept.out).document();
    const Json substituted = JsonReader(expanded.out).document();
    const Json* definitions = with_names.get("definitions");
    REQUIRE(definitions);
    CHECK(!definitions->items.empty());
    REQUIRE(substituted.get("definitions"));
    CHECK(substituted.get("definitions")->items.empty());

    const nhc::Scene scene = nhc::load_scene(example(name));
    std::map<std::string, GiNaC::ex> value_of;  // each definition over the jet symbols
    nhc::ExpressionRules read_back;
    read_back.allow_multipliers = true;
    read_back.input_limits = false;
    read_back.definition = [&](const std::string& n) -> std::optional<nhc::Value> {
      const auto it = value_of.find(n);
      if (it == value_of.end()) return std::nullopt;
      return nhc::Value::scalar(it->second);
    };
    for (const Json& d : definitions->items) {
      REQUIRE(d.get("name"));
      REQUIRE(d.get("expression"));
      INFO("definition " << d.get("name")->s);
      // Dependency order: each names only the ones before it.
      value_of[d.get("name")->s] = nhc::parse_expression(d.get("expression")->s, *scene.jet, read_back);
    }
    const Json& a = *with_names.get("models")->get("chetaev");
    const Json& b = *substituted.get("models")->get("chetaev");
    for (const char* list : {"equations", "constraints"}) {
      REQUIRE(a.get(list)->items.size() == b.get(list)->items.size());
      for (std::size_t i = 0; i < a.get(list)->items.size(); ++i) {
        INFO(list << " " << i << ": " << a.get(list)->items[i].s);
        const GiNaC::ex x = nhc::parse_expression(a.get(list)->items[i].s, *scene.jet, read_back);
        const GiNaC::ex y = nhc::parse_expression(b.get(list)->items[i].s, *scene.jet, read_back);
        CHECK(nhc::vanishes_at_sample_points(x - y));
        CHECK(!nhc::vanishes_at_sample_points(x - y + 1e-6 * scene.jet->parameter(0)));
      }
    }
  }
}

TEST_CASE("derive --expand substitutes every definition: a chain too large expanded is refused where it grows",
          "[cli][intermediates]") {
  // Chains of definitions whose expansion doubles at every link (tests/cli/scenes). Kept (the
  // default) they derive; expanded they are refused at the definition that crosses a size limit,
  // with its file, line and column.
  const std::string dir = scratch_dir("expand_refused");
  for (const auto& [name, where] : std::vector<std::pair<std::string, std::string>>{
           {"definitions_used_too_often", "96:8"}, {"expression_too_large", "22:8"}}) {
    INFO(name);
    const std::string scene = std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/" + name + ".toml";
    const Run kept = run(nhc_command() + " derive '" + scene + "'", dir);
    CHECK(kept.exit_code == 0);
    CHECK(kept.out.find("where") != std::string::npos);
    const Run expanded = run(nhc_command() + " derive '" + scene + "' --expand", dir);
    CHECK(expanded.exit_code == 2);
    CHECK(expanded.err.rfind(scene + ":" + where + ": error: ", 0) == 0);
  }
}

TEST_CASE("JSON output is the same on stdout and with -o", "[cli][json]") {
  const std::string dir = scratch_dir("json_stdout");
  const Run a = run(nhc_command() + " derive '" + example("appell_hamel") + "' --format json", dir);
  const Run b =
      run(nhc_command() + " derive '" + example("appell_hamel") + "' --format json -o '" + dir + "/o.json'", dir);
  REQUIRE(a.exit_code == 0);
  REQUIRE(b.exit_code == 0);
  CHECK(a.out == read_file(dir + "/o.json"));
  CHECK(b.out.empty());
}

TEST_CASE("LaTeX output of the examples compiles with pdflatex, the Whipple bicycle in at most 10 pages",
          "[cli][latex]") {
  // scripts/setup.sh installs pdflatex: without it this test fails rather than passing unchecked.
  INFO("pdflatex is not installed (Debian: apt-get install texlive-latex-base; scripts/setup.sh does)");
  REQUIRE(std::system("command -v pdflatex >/dev/null 2>&1") == 0);
  for (const std::string path : {"particle", "appell_hamel", "whipple/whipple_bicycle"}) {
    INFO("scene " << path);
    const std::string name = path.substr(path.find('/') + 1);
    const std::string dir = scratch_dir("latex_" + name);
    const std::string tex = dir + "/" + name + ".tex";
    const Run r = run(nhc_command() + " derive '" + example(path) + "' --format latex -o '" + tex + "'", dir);
    REQUIRE(r.exit_code == 0);
    const std::string text = read_file(tex);
    CHECK(text.find("\\documentclass") != std::string::npos);
    CHECK(text.find("\\dot{") != std::string::npos);
    CHECK(text.find("\\lambda_{1}") != std::string::npos);
    const Run latex = run(
        "cd '" + dir + "' && pdflatex -interaction=nonstopmode -halt-on-error '" + std::string(name) + ".tex'", dir);
    INFO(latex.out.substr(latex.out.size() > 3000 ? latex.out.size() - 3000 : 0));
    CHECK(latex.exit_code == 0);
    CHECK(file_exists(dir + "/" + name + ".pdf"));
    // "Output written on NAME.pdf (N pages, …)": the goal is the bicycle on a few pages (its
    // equations over its definitions, then the definitions) where expanded it took 299.
    std::smatch pages;
    REQUIRE(std::regex_search(latex.out, pages, std::regex(R"(\((\d+) pages?,)")));
    if (name == "whipple_bicycle") CHECK(std::stoi(pages[1].str()) <= 10);
  }
}

TEST_CASE("LaTeX reads like a textbook: d/dt of partials, like terms gathered, equations named by coordinate",
          "[cli][latex]") {
  const std::string dir = scratch_dir("latex_textbook");
  // R_x = -2 mw x'' - mb x'' + ...: one term in x'' once gathered; Iby next to psi'' spaced.
  const std::string scene = dir + "/cart.toml";
  std::ofstream(scene) << "name = \"cart\"\ncoordinates = [\"x\", \"psi\", \"q1\"]\n"
                          "lagrangian = \"mw*x'^2 + mb/2*x'^2 + Iby/2*psi'^2 + mb*x'*psi'*cos(psi) + q1'^2/2\"\n"
                          "[parameters]\nmw = 1\nmb = 2\nIby = 3\n";
  const Run latex = run(nhc_command() + " derive '" + scene + "' --model chetaev --format latex", dir);
  REQUIRE(latex.exit_code == 0);
  const std::string& t = latex.out;
  const std::size_t rx = t.find("R_{x} &="), rpsi = t.find("R_{\\psi} &=");
  REQUIRE(rx != std::string::npos);
  REQUIRE(rpsi != std::string::npos);
  const std::string row_x = t.substr(rx, t.find('\n', rx) - rx);
  std::size_t accelerations = 0;
  for (std::size_t at = row_x.find("\\ddot{x}"); at != std::string::npos; at = row_x.find("\\ddot{x}", at + 1))
    ++accelerations;
  CHECK(accelerations == 1);
  CHECK(row_x.find("\\mathrm{mw}") != std::string::npos);
  CHECK(t.find("\\mathrm{Iby}\\,\\ddot{\\psi}") != std::string::npos);
  CHECK(t.find("R_{q_{1}} &=") != std::string::npos);
  CHECK(t.find("\\ddot{q}_{1}") != std::string::npos);
  CHECK(t.find("R_{1}") == std::string::npos);

  // The text, LaTeX and JSON name the equations alike.
  const Run json = run(nhc_command() + " derive '" + scene + "' --model chetaev --format json", dir);
  REQUIRE(json.exit_code == 0);
  CHECK(json.out.find("\"equation_names\": [\n        \"R_x\",\n        \"R_psi\",\n        \"R_q1\"") !=
        std::string::npos);

  // The bicycle's time derivatives of partial derivatives: d/dt before the fraction, never a dot over it.
  const Run bicycle =
      run(nhc_command() + " derive '" + example("whipple/whipple_bicycle") + "' --form reduced --format latex", dir);
  REQUIRE(bicycle.exit_code == 0);
  CHECK(bicycle.out.find("\\frac{d}{dt}\\frac{\\partial ") != std::string::npos);
  CHECK(bicycle.out.find("\\dot{\\partial") == std::string::npos);
  CHECK(bicycle.out.find("\\dot{\\frac") == std::string::npos);
  // Multi-letter names of definitions and of coordinates in subscripts upright, like the
  // coordinates: \mathrm{mB}\,\mathrm{vB}_{1}, not mB vB_{1} (v times B_1); C_{\psi,\mathrm{thf}}.
  CHECK(bicycle.out.find("\\mathrm{mB}\\,\\mathrm{vB}_{1}") != std::string::npos);
  CHECK(bicycle.out.find("vB_{") == std::string::npos);
  CHECK(bicycle.out.find("C_{\\psi,\\mathrm{thf}}") != std::string::npos);
  CHECK(bicycle.out.find(",thf}") == std::string::npos);

  // The math-only form has no document structure (MathJax renders math, not \section).
  const Run math = run(nhc_command() + " derive '" + scene + "' --format latex-math", dir);
  REQUIRE(math.exit_code == 0);
  CHECK(math.out.find("\\section") == std::string::npos);
  CHECK(math.out.find("\\documentclass") == std::string::npos);
  CHECK(math.out.find("&\\text{Model }\\mathtt{chetaev}") != std::string::npos);
}

TEST_CASE("the reduced form's forcing reads without accelerations", "[cli][reduced]") {
  // f_r = C^T (r + K w) holds no q'' (docs/reduced-form.md): written as C^T (R + K (w - q'')) the
  // sleigh's f_r[x'] carried m (h_1/cos th + y'') - m y'', like terms apart.
  const std::string dir = scratch_dir("reduced_forcing");
  const Run r =
      run(nhc_command() + " derive '" + example("chaplygin_sleigh") + "' --model chetaev --form reduced", dir);
  REQUIRE(r.exit_code == 0);
  std::istringstream lines(r.out);
  int forcing_rows = 0;
  for (std::string line; std::getline(lines, line);)
    if (line.find("f_r[") != std::string::npos) {
      INFO(line);
      CHECK(line.find("_d2") == std::string::npos);
      ++forcing_rows;
    }
  CHECK(forcing_rows == 2);
}

TEST_CASE("constraints of order two or more have no multiplier-free form, said in words", "[cli][reduced]") {
  // docs/reduced-form.md, "Constraints of higher order": a second-order constraint leaves every
  // speed a state; a third-order one makes the accelerations states.
  const std::string dir = scratch_dir("reduced_higher_order");
  const std::string scene = dir + "/second.toml";
  std::ofstream(scene) << "name = \"second\"\ncoordinates = [\"x\", \"y\"]\n"
                          "lagrangian = \"1/2*(x'^2 + y'^2) - 1/2*(x^2 + y^2)\"\n"
                          "constraints = [\"x'' + c*y''\"]\nmodels = [\"chetaev\"]\n[parameters]\nc = 0.5\n";
  const Run second = run(nhc_command() + " derive '" + scene + "' --form reduced", dir);
  REQUIRE(second.exit_code == 0);
  CHECK(second.out.find("not available: constraint f1 is of order 2: it leaves every speed a state") !=
        std::string::npos);
  const Run third = run(nhc_command() + " derive '" + example("third_order") + "' --form reduced", dir);
  REQUIRE(third.exit_code == 0);
  CHECK(third.out.find("not available: constraint f1 is of order 3: its multiplier is fixed only by the "
                       "derivatives of the second-order equations") != std::string::npos);
}

TEST_CASE("every example's LaTeX document compiles with pdflatex", "[cli][latex]") {
  REQUIRE(std::system("command -v pdflatex >/dev/null 2>&1") == 0);  // scripts/setup.sh installs it
  std::vector<std::string> scenes;
  for (const std::string& name : list_dir(std::string(NHC_SOURCE_DIR) + "/examples", ".toml"))
    scenes.push_back(name.substr(0, name.size() - 5));
  REQUIRE(scenes.size() >= 10);
  for (const std::string& name : scenes) {
    INFO("scene " << name);
    const std::string dir = scratch_dir("latex_all_" + name);
    const Run r = run(nhc_command() + " derive '" + example(name) + "' --format latex -o '" + dir + "/e.tex'", dir);
    REQUIRE(r.exit_code == 0);
    const Run latex = run("cd '" + dir + "' && pdflatex -interaction=nonstopmode -halt-on-error e.tex", dir);
    INFO(latex.out.substr(latex.out.size() > 2000 ? latex.out.size() - 2000 : 0));
    CHECK(latex.exit_code == 0);
  }
}
