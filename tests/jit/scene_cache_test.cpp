// [jit][scene-cache]: the scene-level cache (nhc/jit/scene_cache.hpp). A warm build of an
// unchanged scene derives nothing (derive_model_calls() does not move) and its model still gives
// the closed-form answer; any change of the scene text, parameter values, model, options or nhc
// version is a miss; a damaged or unsafe entry is rebuilt with a warning, never used.
//
// Closed form (models.md, Appell–Hamel under Chetaev's model; k = b/a): from x' = 1, y' = 0.5
// the speed falls as v = v0 − g k t/(1 + k^2) and z' = k v.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/jit.hpp"
#include "nhc/jit/cache_size.hpp"
#include "nhc/jit/scene_cache.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene_builder.hpp"

namespace fs = std::filesystem;

namespace {

std::string appell_hamel_text(const std::string& b = "0.5", const std::string& extra = "") {
  return "name = \"appell_hamel\"\n"
         "coordinates = [\"x\", \"y\", \"z\"]\n"
         "lagrangian = \"m/2*(x'^2 + y'^2 + z'^2) - m*g*z\"\n"
         "constraints = [\"z' - b/a*sqrt(x'^2 + y'^2)\"]\n" +
         extra + "[parameters]\nm = 1.0\ng = 9.81\na = 1.0\nb = " + b +
         "\n[initial]\nt0 = 0.0\nx = [0.0, 1.0]\ny = [0.0, 0.5]\nz = [0.0]\n";
}

nhc::Scene scene_of(const std::string& text) { return nhc::parse_scene(text, "appell_hamel.toml"); }

fs::path fresh_cache(const std::string& name) {
  const fs::path dir = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / name;
  fs::remove_all(dir);
  return dir;
}

struct Builder {
  explicit Builder(fs::path directory) : cache(std::move(directory)) {}
  fs::path cache;
  std::vector<std::string> warnings;

  nhc::jit::BuildOptions options() {
    nhc::jit::BuildOptions o;
    o.compile.cache_directory = cache;
    o.compile.warn = [this](const std::string& line) { warnings.push_back(line); };
    return o;
  }
  /// Builds and returns how many derivations it took.
  long derivations(const nhc::Scene& scene, nhc::jit::BuildOptions o, nhc::ModelKind kind = nhc::ModelKind::chetaev) {
    const long before = nhc::derive_model_calls();
    last.emplace(nhc::jit::build(scene, kind, o));
    return nhc::derive_model_calls() - before;
  }
  long derivations(const nhc::Scene& scene) { return derivations(scene, options()); }
  std::optional<nhc::jit::LoadedModel> last;
};

/// The largest |z' − k v| over t in [0, 0.25] (well before the stop at t* ≈ 0.57).
double z_dot_error(const nhc::runtime::Model& model, double b) {
  using namespace nhc::runtime;
  IntegratorOptions options;
  options.rtol = 1e-9;
  options.atol = 1e-11;
  const double v0 = std::hypot(1.0, 0.5), k = b;
  const std::map<std::string, std::vector<double>> values{{"x", {0.0, 1.0}}, {"y", {0.0, 0.5}}, {"z", {0.0}}};
  const RunResult run = simulate(model, model.default_parameters(), initial_state_from(model, 0.0, values),
                                 output_times(0.0, 0.25, 10), options);
  REQUIRE_FALSE(run.failure);
  double worst = 0;
  for (const Sample& s : run.samples)
    worst = std::max(worst, std::abs(s.y[5] - k * (v0 - 9.81 * k * s.t / (1 + k * k))));
  return worst;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

fs::path header_entry(const Builder& builder, const nhc::Scene& scene, const std::string& options) {
  const auto key = nhc::jit::scene_cache_key(scene, "generated header", options, nhc::jit::scene_cache_version(),
                                             nhc::jit::FingerprintScope::equations);
  REQUIRE(key);
  return builder.cache / "scenes" / (*key + ".entry");
}

}  // namespace

TEST_CASE("an unchanged scene builds from the scene cache without deriving", "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_warm")};
  REQUIRE(builder.derivations(scene_of(appell_hamel_text())) == 1);
  REQUIRE_FALSE(builder.last->timings().scene_cached);
  const std::string cold_header = builder.last->header().text;
  const double cold_error = z_dot_error(builder.last->model(), 0.5);

  // A new Scene object read from the same text: nothing derived, the same header and answer.
  REQUIRE(builder.derivations(scene_of(appell_hamel_text())) == 0);
  REQUIRE(builder.last->timings().scene_cached);
  REQUIRE(builder.last->timings().derive == 0);
  REQUIRE(builder.last->library().reused);
  CHECK(builder.last->header().text == cold_header);
  CHECK(builder.last->header().namespace_name == "appell_hamel_chetaev");
  CHECK(builder.last->jacobian() == nhc::JacobianKind::dense);
  const double warm_error = z_dot_error(builder.last->model(), 0.5);
  CHECK(warm_error < 1e-6);
  CHECK(warm_error == cold_error);
  CHECK(builder.warnings.empty());
}

TEST_CASE("any change of the equations' text, parameters, model, options or version is a scene-cache miss",
          "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_invalidation")};
  const nhc::Scene scene = scene_of(appell_hamel_text());
  REQUIRE(builder.derivations(scene) == 1);
  REQUIRE(builder.derivations(scene) == 0);

  SECTION("a comment added to the text finds the same header, a changed constraint does not") {
    CHECK(builder.derivations(scene_of(appell_hamel_text("0.5", "# a comment\n"))) == 0);
    std::string text = appell_hamel_text();
    text.replace(text.find("z' - b/a"), 8, "z' - 2*b/a");
    CHECK(builder.derivations(scene_of(text)) == 1);
    CHECK(builder.derivations(scene_of(text)) == 0);
  }
  SECTION("a parameter changed in the text: the new model has the new value") {
    CHECK(builder.derivations(scene_of(appell_hamel_text("0.25"))) == 1);
    const int b = builder.last->model().parameter_index("b");
    REQUIRE(b >= 0);
    CHECK(builder.last->model().default_parameters()[static_cast<std::size_t>(b)] == 0.25);
    CHECK(z_dot_error(builder.last->model(), 0.25) < 1e-6);
  }
  SECTION("a parameter changed in code, as --set does") {
    nhc::Scene set = scene;
    set.parameter_values[3] = 0.25;
    CHECK(builder.derivations(set) == 1);
    CHECK(builder.derivations(set) == 0);
  }
  SECTION("initial data and run settings, changed in code or in the text, find the same header") {
    // The header takes them at run time: keyed by what it is made from, it is found
    // again; the initial-point check, which depends on them, keeps a key of everything.
    nhc::Scene changed = scene;
    changed.initial.values["x"] = {0.0, 2.0};
    CHECK(builder.derivations(changed) == 0);
    CHECK(*nhc::jit::scene_cache_key(changed, "initial point check", "") !=
          *nhc::jit::scene_cache_key(scene, "initial point check", ""));
    changed = scene;
    changed.simulate.rtol = 1e-6;
    CHECK(builder.derivations(changed) == 0);
    std::string text = appell_hamel_text() + "[simulate]\nt_end = 7.5\n";
    text.replace(text.find("y = [0.0, 0.5]"), 14, "y = [0.0, 0.25]");
    CHECK(builder.derivations(scene_of(text)) == 0);
  }
  SECTION("the same text under another file name (the banner names it)") {
    CHECK(builder.derivations(nhc::parse_scene(appell_hamel_text(), "elsewhere/other.toml")) == 1);
  }
  SECTION("another model, Jacobian or sensitivities") {
    CHECK(builder.derivations(scene, builder.options(), nhc::ModelKind::vakonomic) == 1);
    CHECK(builder.derivations(scene, builder.options(), nhc::ModelKind::vakonomic) == 0);
    auto sparse = builder.options();
    sparse.jacobian = nhc::JacobianKind::sparse;
    CHECK(builder.derivations(scene, sparse) == 1);
    CHECK(builder.last->jacobian() == nhc::JacobianKind::sparse);
    CHECK(builder.derivations(scene, sparse) == 0);
    CHECK(builder.last->jacobian() == nhc::JacobianKind::sparse);
    auto sensitivities = builder.options();
    sensitivities.sensitivities = true;
    CHECK(builder.derivations(scene, sensitivities) == 1);
    CHECK(builder.last->model().has_parameter_jacobian());
  }
  SECTION("another nhc version: another key, its entries not found") {
    const auto key = nhc::jit::scene_cache_key(scene, "generated header", "model chetaev");
    const auto other = nhc::jit::scene_cache_key(scene, "generated header", "model chetaev", "0.0.0-other");
    REQUIRE(key);
    REQUIRE(other);
    CHECK(*key != *other);
    CHECK(*key ==
          *nhc::jit::scene_cache_key(scene, "generated header", "model chetaev", nhc::jit::scene_cache_version()));
    // The version names the code generator's sources: a build from others does not match.
    CHECK(nhc::jit::scene_cache_version().find(NHC_VERSION) == 0);
    CHECK(*key != *nhc::jit::scene_cache_key(scene, "generated header", "model chetaev", NHC_VERSION));
    const nhc::jit::SceneCache cache(builder.cache);
    nhc::jit::SceneCacheRecord record;
    record.set("value", "stored under this version");
    cache.store(*key, record);
    CHECK(cache.load(*key));
    CHECK_FALSE(cache.load(*other));
  }
  SECTION("the cache turned off, and a scene without source text, derive every time") {
    auto off = builder.options();
    off.scene_cache = false;
    CHECK(builder.derivations(scene, off) == 1);
    ::setenv("NHC_SCENE_CACHE", "off", 1);
    CHECK(builder.derivations(scene) == 1);
    ::unsetenv("NHC_SCENE_CACHE");
    nhc::Scene changed_in_code = scene;
    changed_in_code.lagrangian = 2 * changed_in_code.lagrangian;  // a system changed in code
    CHECK_FALSE(nhc::jit::scene_cache_key(changed_in_code, "generated header", ""));
    CHECK(builder.derivations(changed_in_code) == 1);
    CHECK(builder.derivations(changed_in_code) == 1);
  }
  SECTION("a SceneBuilder scene is cached by the text it is built from") {
    auto built = [](double b) {
      return nhc::SceneBuilder("appell_hamel")
          .coordinates({"x", "y", "z"})
          .parameter("m", 1.0)
          .parameter("g", 9.81)
          .parameter("a", 1.0)
          .parameter("b", b)
          .lagrangian("m/2*(x'^2 + y'^2 + z'^2) - m*g*z")
          .constraint("z' - b/a*sqrt(x'^2 + y'^2)")
          .build();
    };
    CHECK(builder.derivations(built(0.5)) == 1);
    CHECK(builder.derivations(built(0.5)) == 0);
    CHECK(builder.derivations(built(0.25)) == 1);
  }
  CHECK(builder.warnings.empty());
}

TEST_CASE("the reduced form's speeds chosen at the initial point are part of the header's key", "[jit][scene-cache]") {
  // The knife edge x' sin(phi) = y' cos(phi) with no `dependent` key: the default rule makes y
  // dependent from phi = 0 (speeds x', phi') and x from phi = pi/2 or 0.3 (speeds y', phi';
  // docs/reduced-form.md). M_r's first entry, T = m/2 (x'^2 + y'^2) on the chosen speed, is
  // m / cos^2(phi) or m / sin^2(phi).
  auto knife_edge = [](const std::string& phi0) {
    return nhc::parse_scene(
        "name = \"knife_edge\"\ncoordinates = [\"x\", \"y\", \"phi\"]\n"
        "lagrangian = \"m/2*(x'^2 + y'^2) + J/2*phi'^2\"\n"
        "constraints = [\"x'*sin(phi) - y'*cos(phi)\"]\nmodels = [\"chetaev\"]\n"
        "[parameters]\nm = 2.0\nJ = 0.5\n[initial]\nt0 = 0.0\nx = [0.0]\ny = [0.0]\nphi = [" +
            phi0 + "]\n",
        "knife_edge.toml");
  };
  Builder builder{fresh_cache("scene_cache_reduced_speeds")};
  auto options = builder.options();
  options.reduced_form = true;
  auto speeds = [&] {
    const nhc::runtime::Model& m = builder.last->model();
    std::vector<int> out;
    for (int k = 0; k < m.n_speeds(); ++k) out.push_back(m.speed_coordinate(k));
    return out;
  };
  auto first_mass = [&](double phi) {
    const nhc::runtime::Model& m = builder.last->model();
    const std::vector<double> q{0.1, 0.2, phi}, u{0.5, 0.3}, p = m.default_parameters();
    std::vector<double> M(4);
    m.table().mass_matrix(0.0, q.data(), u.data(), p.data(), M.data());
    return M[0];
  };
  REQUIRE(builder.derivations(knife_edge("0.0"), options) == 1);
  CHECK(speeds() == std::vector<int>{0, 2});
  CHECK(first_mass(0.4) == Approx(2.0 / std::pow(std::cos(0.4), 2)).epsilon(1e-12));
  // Another start with another choice: derived again, on its own speeds (not the cached ones).
  CHECK(builder.derivations(knife_edge("1.5707963267948966"), options) == 1);
  CHECK(speeds() == std::vector<int>{1, 2});
  CHECK(first_mass(0.4) == Approx(2.0 / std::pow(std::sin(0.4), 2)).epsilon(1e-12));
  // A start with the same choice finds that header; without the reduced form every start does.
  CHECK(builder.derivations(knife_edge("0.3"), options) == 0);
  CHECK(speeds() == std::vector<int>{1, 2});
  CHECK(builder.derivations(knife_edge("0.0"), options) == 0);
  CHECK(speeds() == std::vector<int>{0, 2});
  CHECK(builder.derivations(knife_edge("0.0")) == 1);
  CHECK(builder.derivations(knife_edge("1.5707963267948966")) == 0);
  CHECK(builder.warnings.empty());
}

TEST_CASE("a damaged or unsafe scene-cache entry is rebuilt with a warning, never used", "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_damage")};
  const nhc::Scene scene = scene_of(appell_hamel_text());
  REQUIRE(builder.derivations(scene) == 1);
  const fs::path entry = header_entry(builder, scene,
                                      "model chetaev, jacobian default, sensitivities no, split from " +
                                          std::to_string(nhc::HeaderOptions{}.split_from_bytes) + " bytes");
  REQUIRE(fs::is_regular_file(entry));
  const std::string good = read_file(entry);
  CHECK((fs::status(entry).permissions() & (fs::perms::group_all | fs::perms::others_all)) == fs::perms::none);

  std::string expected;
  SECTION("truncated") {
    write_file(entry, good.substr(0, good.size() / 2));
    expected = "truncated or damaged";
  }
  SECTION("one byte of the payload changed") {
    std::string bad = good;
    const std::size_t at = bad.find("nhc_gen");
    REQUIRE(at != std::string::npos);
    bad[at] = 'N';
    write_file(entry, bad);
    expected = "does not match its SHA-256 digest";
  }
  SECTION("garbage") {
    write_file(entry, std::string(3000, '\x7f'));
    expected = "not a scene cache entry";
  }
  SECTION("another key's entry in its place") {
    nhc::jit::SceneCacheRecord record;
    record.set("text", "int x;");
    const nhc::jit::SceneCache cache(builder.cache);
    cache.store(std::string(64, 'a'), record);
    fs::rename(builder.cache / "scenes" / (std::string(64, 'a') + ".entry"), entry);
    expected = "it holds another key";
  }
  SECTION("writable by others") {
    fs::permissions(entry, fs::perms::others_write, fs::perm_options::add);
    expected = "writable by others";
  }
  SECTION("a symbolic link") {
    const fs::path elsewhere = builder.cache / "elsewhere.entry";
    fs::rename(entry, elsewhere);
    fs::create_symlink(elsewhere, entry);
    expected = "symbolic link";
  }
  CHECK(builder.derivations(scene) == 1);
  REQUIRE(builder.warnings.size() == 1);
  CHECK(builder.warnings[0].find("scene cache entry " + entry.string() + " rejected: ") == 0);
  CHECK(builder.warnings[0].find(expected) != std::string::npos);
  CHECK(z_dot_error(builder.last->model(), 0.5) < 1e-6);
  // Rebuilt: the next build uses it again.
  CHECK(read_file(entry) == good);
  CHECK(builder.derivations(scene) == 0);
  CHECK(builder.warnings.size() == 1);
}

TEST_CASE("scene-cache records hold any bytes and refuse malformed text", "[jit][scene-cache]") {
  nhc::jit::SceneCacheRecord record;
  const std::string binary("line\n2\0three\n\n", 14);
  record.set("binary", binary);
  record.set("empty", "");
  record.set("name with space", "v");
  const auto parsed = nhc::jit::SceneCacheRecord::parse(record.serialize());
  REQUIRE(parsed);
  CHECK(parsed->get("binary") == binary);
  CHECK(parsed->get("empty") == std::string());
  CHECK(parsed->get("name with space") == std::string("v"));
  CHECK_FALSE(parsed->get("missing"));
  const std::string text = record.serialize();
  CHECK_FALSE(nhc::jit::SceneCacheRecord::parse(text.substr(0, text.size() - 1)));
  CHECK_FALSE(nhc::jit::SceneCacheRecord::parse("field 99\nshort\n"));
  CHECK_FALSE(nhc::jit::SceneCacheRecord::parse("no length\n"));
  CHECK(nhc::jit::SceneCacheRecord::parse(""));
}

namespace {

/// Appell–Hamel with a table of every part: the system's (derived parameter, input, force,
/// invariant, reference), the experiment's ([initial], [simulate], [events]) and the
/// presentation's ([outputs], [visual]).
std::string every_part_text() {
  return "name = \"appell_hamel\"\n"
         "coordinates = [\"x\", \"y\", \"z\"]\n"
         "lagrangian = \"m/2*(x'^2 + y'^2 + z'^2) - m*g*z\"\n"
         "constraints = [\"z' - k*sqrt(x'^2 + y'^2)\"]\n"
         "[parameters]\nm = 1.0\ng = 9.81\na = 1.0\nb = 0.5\nk = \"b/a\"\n"
         "[inputs]\nu = \"0.1*t\"\n"
         "[forces]\nx = \"u - 0.01*x'\"\n"
         "[invariants]\nspeed = \"x'^2 + y'^2\"\n"
         "[reference]\ny = \"0.5*t\"\n"
         "[initial]\nt0 = 0.0\nx = [0.0, 1.0]\ny = [0.0, 0.5]\nz = [0.0]\n"
         "[simulate]\nt_end = 0.5\n"
         "[events]\nhigh = { when = \"z - 1\", direction = \"up\", action = \"stop\" }\n"
         "[outputs]\nv = \"sqrt(x'^2 + y'^2)\"\n"
         "[visual]\npath = { shape = \"trace\", point = \"[x, y, z]\" }\n";
}

std::optional<std::string> header_key(const nhc::Scene& scene) {
  return nhc::jit::scene_cache_key(scene, "generated header", "model chetaev", nhc::jit::scene_cache_version(),
                                   nhc::jit::FingerprintScope::equations);
}

}  // namespace

TEST_CASE("the system's key follows every change of the system and no change of the experiment or the presentation",
          "[jit][scene-cache]") {
  const nhc::Scene scene = scene_of(every_part_text());
  REQUIRE(scene.derived_parameters.size() == 1);
  REQUIRE(scene.inputs.size() == 1);
  REQUIRE(scene.invariants.size() == 1);
  REQUIRE(scene.reference.all.size() == 1);
  REQUIRE(scene.events.size() == 1);
  REQUIRE(scene.outputs.size() == 1);
  REQUIRE(scene.visuals.size() == 1);
  const std::optional<std::string> system = nhc::jit::system_fingerprint(scene);
  const std::optional<std::string> header = header_key(scene);
  REQUIRE(system);
  REQUIRE(header);
  CHECK(nhc::jit::system_fingerprint(nhc::Scene(scene)) == system);  // a copy is the same system

  SECTION("the experiment or the presentation changed in code: the same system, the same header") {
    using Change = std::function<void(nhc::Scene&)>;
    const std::vector<std::pair<const char*, Change>> changes{
        {"t0", [](nhc::Scene& s) { s.initial.t0 = 1.0; }},
        {"initial value",
         [](nhc::Scene& s) {
           s.initial.values["x"] = {0.0, 2.0};
         }},
        {"initial expression",
         [](nhc::Scene& s) {
           s.initial.expressions["x"] = {"", "b"};
         }},
        {"fixed", [](nhc::Scene& s) { s.initial.fixed.push_back("x"); }},
        {"model", [](nhc::Scene& s) { s.simulate.model = nhc::ModelKind::vakonomic; }},
        {"t_end", [](nhc::Scene& s) { s.simulate.t_end = 9.0; }},
        {"rtol", [](nhc::Scene& s) { s.simulate.rtol = 1e-4; }},
        {"atol", [](nhc::Scene& s) { s.simulate.atol = 1e-4; }},
        {"output intervals", [](nhc::Scene& s) { s.simulate.outputs = 7; }},
        {"event", [](nhc::Scene& s) { s.events.front().expression = s.events.front().expression - 1; }},
        {"events", [](nhc::Scene& s) { s.events.clear(); }},
        {"contact",
         [](nhc::Scene& s) {
           s.contacts.push_back({"floor", s.jet->parameter(0), "m", {}, {}, {0}, 0.3, {}});
         }},
        {"output", [](nhc::Scene& s) { s.outputs.front().expression = 2 * s.outputs.front().expression; }},
        {"outputs", [](nhc::Scene& s) { s.outputs.clear(); }},
        {"visuals", [](nhc::Scene& s) { s.visuals.clear(); }},
        {"warnings", [](nhc::Scene& s) { s.warnings.push_back("a warning"); }},
    };
    for (const auto& [what, change] : changes) {
      INFO(what);
      nhc::Scene changed = scene;
      change(changed);
      CHECK(changed.source_text() == scene.source_text());
      CHECK(nhc::jit::system_fingerprint(changed) == system);
      CHECK(header_key(changed) == header);
    }
    // The parameter values are the header's defaults: its key has them, the system's does not.
    nhc::Scene set = scene;
    set.parameter_values[3] = 0.25;
    CHECK(nhc::jit::system_fingerprint(set) == system);
    CHECK(header_key(set) != header);
  }
  SECTION("the experiment's and the presentation's tables changed in the text: the same system") {
    std::string text = every_part_text();
    text.replace(text.find("t_end = 0.5"), 11, "t_end = 2.5");
    text.replace(text.find("x = [0.0, 1.0]"), 14, "x = [0.0, 3.0]");
    text.replace(text.find("\"z - 1\""), 7, "\"z - 2\"");
    text.replace(text.find("\"sqrt(x'^2 + y'^2)\""), 19, "\"x'\"");
    text.replace(text.find("[x, y, z]"), 9, "[x, y, 0]");
    const nhc::Scene changed = scene_of(text);
    CHECK(nhc::jit::system_fingerprint(changed) == system);
    CHECK(header_key(changed) == header);
  }
  SECTION("any field of the system changed in code: no key, nothing cached") {
    using Change = std::function<void(nhc::Scene&)>;
    const std::vector<std::pair<const char*, Change>> changes{
        {"name", [](nhc::Scene& s) { s.name = "other"; }},
        {"source_path", [](nhc::Scene& s) { s.source_path = "other.toml"; }},
        {"keep_definitions", [](nhc::Scene& s) { s.keep_definitions = !s.keep_definitions; }},
        {"jet", [](nhc::Scene& s) { s.jet = std::make_shared<nhc::JetSpace>(*s.jet); }},
        {"derived parameter", [](nhc::Scene& s) { s.derived_parameters.front().value *= 2; }},
        {"lagrangian", [](nhc::Scene& s) { s.lagrangian = 2 * s.lagrangian; }},
        {"lagrangian_where", [](nhc::Scene& s) { s.lagrangian_where.line += 1; }},
        {"constraint", [](nhc::Scene& s) { s.constraints.front() = 2 * s.constraints.front(); }},
        {"constraint added", [](nhc::Scene& s) { s.constraints.push_back(s.constraints.front()); }},
        {"constraint text", [](nhc::Scene& s) { s.constraint_texts.front() += " "; }},
        {"dependent", [](nhc::Scene& s) { s.dependent = {2}; }},
        {"models", [](nhc::Scene& s) { s.models.pop_back(); }},
        {"force", [](nhc::Scene& s) { s.forces.front() = -s.forces.front(); }},
        {"input name", [](nhc::Scene& s) { s.inputs.front().name = "w"; }},
        {"input signal", [](nhc::Scene& s) { s.inputs.front().default_signal = 0.2 * s.jet->time(); }},
        {"input law", [](nhc::Scene& s) { s.inputs.front().law = s.jet->q(0, 0); }},
        {"input feedback", [](nhc::Scene& s) { s.inputs.front().feedback = true; }},
        {"invariant", [](nhc::Scene& s) { s.invariants.front().expression = 3 * s.invariants.front().expression; }},
        {"invariant required", [](nhc::Scene& s) { s.invariants.front().required = true; }},
        {"reference", [](nhc::Scene& s) { s.reference.all.front().second = s.jet->time(); }},
        {"reference per model",
         [](nhc::Scene& s) { s.reference.per_model[nhc::ModelKind::vakonomic] = s.reference.all; }},
    };
    for (const auto& [what, change] : changes) {
      INFO(what);
      nhc::Scene changed = scene;
      change(changed);
      CHECK(changed.source_text().empty());
      CHECK_FALSE(nhc::jit::system_fingerprint(changed));
      CHECK_FALSE(header_key(changed));
      CHECK_FALSE(nhc::jit::scene_cache_key(changed, "initial point check", ""));
      // Recording the text again makes it stand for the system as it now is.
      changed.set_source_text(scene.source_text());
      CHECK(nhc::jit::system_fingerprint(changed));
    }
  }
}

namespace {

nhc::jit::BuildOptions interpreted(nhc::jit::BuildOptions o) {
  o.backend = nhc::jit::Backend::interpreted;
  return o;
}

fs::path program_entry(const Builder& builder, const nhc::Scene& scene) {
  const auto key = nhc::jit::scene_cache_key(scene, "interpreted program",
                                             "model chetaev, jacobian default, sensitivities no, split from " +
                                                 std::to_string(nhc::HeaderOptions{}.split_from_bytes) + " bytes",
                                             nhc::jit::scene_cache_version(), nhc::jit::FingerprintScope::equations);
  REQUIRE(key);
  return builder.cache / "scenes" / (*key + ".entry");
}

/// The residual's bits at a point of no particular meaning: equal programs give equal bits.
std::vector<double> residual_at(const nhc::runtime::Model& model) {
  const nhc_model_table& t = model.table();
  std::vector<double> y(static_cast<std::size_t>(t.n_states)), yp(y.size()), r(y.size());
  for (std::size_t k = 0; k < y.size(); ++k)
    y[k] = 0.3 + 0.1 * static_cast<double>(k), yp[k] = 0.7 - 0.05 * static_cast<double>(k);
  const std::vector<double> p = model.default_parameters();
  t.residual(0.2, y.data(), yp.data(), p.data(), r.data());
  return r;
}

}  // namespace

TEST_CASE("a scene interpreted before builds from its cached program without deriving", "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_program")};
  const std::string text = appell_hamel_text();
  REQUIRE(builder.derivations(scene_of(text), interpreted(builder.options())) == 1);
  REQUIRE(builder.last->timings().interpreted);
  REQUIRE_FALSE(builder.last->timings().scene_cached);
  const std::vector<double> cold_residual = residual_at(builder.last->model());
  const double cold_error = z_dot_error(builder.last->model(), 0.5);
  const std::string cold_header = builder.last->header().text;
  REQUIRE(fs::is_regular_file(program_entry(builder, scene_of(text))));

  // A new Scene read from the same text, interpreted or automatic (never compiled before): no
  // derivation, no lowering, the same bits.
  for (nhc::jit::Backend backend : {nhc::jit::Backend::interpreted, nhc::jit::Backend::automatic}) {
    nhc::jit::BuildOptions o = builder.options();
    o.backend = backend;
    CHECK_FALSE(nhc::jit::build_derives(scene_of(text), nhc::ModelKind::chetaev, o));
    REQUIRE(builder.derivations(scene_of(text), o) == 0);
    CHECK(builder.last->timings().scene_cached);
    CHECK(builder.last->timings().interpreted);
    CHECK(builder.last->header().text == cold_header);  // what a compile behind the run compiles
    CHECK(residual_at(builder.last->model()) == cold_residual);
    CHECK(z_dot_error(builder.last->model(), 0.5) == cold_error);
  }
  // Compiled, the same header gives the same bits too; a compiled build never takes the program.
  nhc::jit::BuildOptions compiled = builder.options();
  compiled.backend = nhc::jit::Backend::compiled;
  CHECK(nhc::jit::build_derives(scene_of(text), nhc::ModelKind::chetaev, compiled));
  REQUIRE(builder.derivations(scene_of(text), compiled) == 1);
  CHECK(residual_at(builder.last->model()) == cold_residual);
  // Another parameter value is another program.
  CHECK(nhc::jit::build_derives(scene_of(appell_hamel_text("0.25")), nhc::ModelKind::chetaev,
                                interpreted(builder.options())));
  CHECK(builder.warnings.empty());
}

TEST_CASE("a damaged or foreign cached program is rejected with a warning and rebuilt", "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_program_damage")};
  const nhc::Scene scene = scene_of(appell_hamel_text());
  REQUIRE(builder.derivations(scene, interpreted(builder.options())) == 1);
  const std::vector<double> good_residual = residual_at(builder.last->model());
  const fs::path entry = program_entry(builder, scene);
  REQUIRE(fs::is_regular_file(entry));
  const std::string good = read_file(entry);
  const auto key = entry.stem().string();
  const nhc::jit::SceneCache cache(builder.cache);
  const std::optional<nhc::jit::SceneCacheRecord> record = cache.load(key);
  REQUIRE(record);
  REQUIRE(record->get("program"));

  std::string expected;
  SECTION("one byte of the program changed") {
    std::string bad = good;
    bad[bad.size() - 40] ^= 0x10;
    write_file(entry, bad);
    expected = "does not match its SHA-256 digest";
  }
  SECTION("truncated") {
    write_file(entry, good.substr(0, good.size() - 7));
    expected = "truncated or damaged";
  }
  // Entries that pass the file's checks (this user's, private, digest and key right) but whose
  // program is not this scene's, or not a program: written by another nhc, or by hand.
  SECTION("a program cut short, with its digest") {
    nhc::jit::SceneCacheRecord bad = *record;
    const std::string program = *record->get("program");
    bad.set("program", program.substr(0, program.size() / 2));
    cache.store(key, bad);
    expected = "not one nhc can run";
  }
  SECTION("the program's last words overwritten, with its digest") {
    nhc::jit::SceneCacheRecord bad = *record;
    std::string program = *record->get("program");
    // Register numbers and counts far beyond the program's.
    for (std::size_t at = program.size() - 64; at < program.size() - 4; at += 4) program[at + 3] = '\x7f';
    bad.set("program", program);
    cache.store(key, bad);
    expected = "not one nhc can run";
  }
  SECTION("another scene's program, with its digest") {
    Builder other{fresh_cache("scene_cache_program_other")};
    std::string text = appell_hamel_text();
    text.replace(text.find("appell_hamel"), 12, "other_scene");
    REQUIRE(other.derivations(scene_of(text), interpreted(other.options())) == 1);
    const fs::path other_entry = program_entry(other, scene_of(text));
    const std::optional<nhc::jit::SceneCacheRecord> foreign =
        nhc::jit::SceneCache(other.cache).load(other_entry.stem().string());
    REQUIRE(foreign);
    cache.store(key, *foreign);
    expected = "not one nhc can run";
  }
  SECTION("writable by others") {
    fs::permissions(entry, fs::perms::others_write, fs::perm_options::add);
    expected = "writable by others";
  }
  CHECK(builder.derivations(scene, interpreted(builder.options())) == 1);
  REQUIRE(builder.warnings.size() == 1);
  CHECK(builder.warnings[0].find("scene cache entry " + entry.string() + " rejected: ") == 0);
  CHECK(builder.warnings[0].find(expected) != std::string::npos);
  CHECK(residual_at(builder.last->model()) == good_residual);
  // Rebuilt and used by the next build. (Not byte for byte the first entry: a derivation again in
  // the same process numbers the instructions, and so the registers, otherwise; the arithmetic
  // and its order are the same, and so are the residual's bits.)
  CHECK(fs::is_regular_file(entry));
  CHECK(builder.derivations(scene, interpreted(builder.options())) == 0);
  CHECK(residual_at(builder.last->model()) == good_residual);
  CHECK(builder.warnings.size() == 1);
}

TEST_CASE("the cache keeps under NHC_CACHE_MAX_SIZE, the longest unused entries removed first", "[jit][scene-cache]") {
  const fs::path directory = fresh_cache("scene_cache_size");
  const nhc::jit::SceneCache cache(directory);
  nhc::jit::SceneCacheRecord record;
  record.set("text", std::string(10000, 'x'));
  ::setenv("NHC_CACHE_MAX_SIZE", "35K", 1);
  const std::vector<std::string> keys{std::string(64, 'a'), std::string(64, 'b'), std::string(64, 'c'),
                                      std::string(64, 'd')};
  for (std::size_t k = 0; k < 3; ++k) cache.store(keys[k], record);
  REQUIRE(cache.load(keys[0]));  // used: now the latest used but the next one stored
  cache.store(keys[3], record);  // four entries of 10 kB: over 35 kB, one removed (90 % of it)
  ::unsetenv("NHC_CACHE_MAX_SIZE");
  CHECK(fs::exists(cache.entry_path(keys[3])));        // just stored
  CHECK(fs::exists(cache.entry_path(keys[0])));        // used last
  CHECK_FALSE(fs::exists(cache.entry_path(keys[1])));  // the longest unused
  CHECK(fs::exists(cache.entry_path(keys[2])));        // three entries fit in 90 % of 35 kB
  CHECK(nhc::jit::cache_size_limit() == (std::uintmax_t{2} << 30));
}
