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
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/jit.hpp"
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
         extra +
         "[parameters]\nm = 1.0\ng = 9.81\na = 1.0\nb = " + b +
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
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, 0.0, values), output_times(0.0, 0.25, 10), options);
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
    // The header takes them at run time (issue 27): keyed by what it is made from, it is found
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
    CHECK(*key == *nhc::jit::scene_cache_key(scene, "generated header", "model chetaev", nhc::jit::scene_cache_version()));
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
    changed_in_code.source_text.clear();  // what code that changes a scene's expressions must do
    CHECK_FALSE(nhc::jit::scene_cache_key(changed_in_code, "generated header", ""));
    CHECK(builder.derivations(changed_in_code) == 1);
    CHECK(builder.derivations(changed_in_code) == 1);
  }
  SECTION("a SceneBuilder scene is cached by the text it is built from") {
    auto built = [](double b) {
      return nhc::SceneBuilder("appell_hamel")
          .coordinates({"x", "y", "z"})
          .parameter("m", 1.0).parameter("g", 9.81).parameter("a", 1.0).parameter("b", b)
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

TEST_CASE("a damaged or unsafe scene-cache entry is rebuilt with a warning, never used", "[jit][scene-cache]") {
  Builder builder{fresh_cache("scene_cache_damage")};
  const nhc::Scene scene = scene_of(appell_hamel_text());
  REQUIRE(builder.derivations(scene) == 1);
  const fs::path entry = header_entry(builder, scene, "model chetaev, jacobian default, sensitivities no, split from " + std::to_string(nhc::HeaderOptions{}.split_from_bytes) + " bytes");
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
