// A scene's model derived, generated, compiled and loaded (build.hpp).
#include "nhc/jit/build.hpp"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/base/clock.hpp"
#include "nhc/long_work.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/errors.hpp"
#include "nhc/jit/interpreted_model.hpp"

namespace nhc::jit {

namespace {

/// The scene and model a generated header is for: its namespace is `<scene>_<model>`
/// (header_emitter.hpp). A header named otherwise (written by hand) has its model checked only.
ModelIdentity identity_of(const GeneratedHeader& header, ModelKind kind) {
  const std::string model = to_string(kind), suffix = "_" + model;
  const std::string& name = header.namespace_name;
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    return {name.substr(0, name.size() - suffix.size()), model};
  return {"", model};
}

/// The reduced form's words in the key: its dependent coordinates, which the default rule may
/// choose at the initial point, not part of the equations' fingerprint (docs/reduced-form.md).
std::string reduced_form_text(const Scene& scene) {
  const std::optional<std::vector<int>> dependent = default_dependent_coordinates(scene);
  if (!dependent) return ", reduced form on no rule's choice";
  std::string out = ", reduced form with dependent";
  for (int d : *dependent) out += " " + std::to_string(d);
  return out;
}

/// The product build() keeps in the scene cache, and the words naming what it depends on
/// besides the scene's equations (the compile options only matter to the compile cache).
constexpr const char* kHeaderProduct = "generated header";
std::string header_options_text(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  return "model " + to_string(kind) + ", jacobian " + (options.jacobian ? to_string(*options.jacobian) : "default") +
         ", sensitivities " + (options.sensitivities ? "yes" : "no") +
         (options.variational ? ", variational step" : "") + (options.reduced_form ? reduced_form_text(scene) : "") +
         ", split from " + std::to_string(options.split_from_bytes) + " bytes";
}

std::string count_text(const OperationCount& c) {
  return std::to_string(c.additions) + " " + std::to_string(c.multiplications) + " " + std::to_string(c.divisions) +
         " " + std::to_string(c.calls);
}

std::optional<OperationCount> parse_count(const std::string& text) {
  OperationCount c;
  std::istringstream in(text);
  std::string rest;
  if (!(in >> c.additions >> c.multiplications >> c.divisions >> c.calls) || (in >> rest)) return std::nullopt;
  return c;
}

SceneCacheRecord header_record(const GeneratedHeader& header, JacobianKind jacobian) {
  SceneCacheRecord record;
  record.set("file_name", header.file_name);
  record.set("namespace", header.namespace_name);
  record.set("text", header.text);
  record.set("operations_before_cse", count_text(header.before_cse));
  record.set("operations_after_cse", count_text(header.after_cse));
  record.set("jacobian", to_string(jacobian));
  return record;
}

struct CachedHeader {
  GeneratedHeader header;
  JacobianKind jacobian;
};

/// The header in a record; nullopt when a field is missing or malformed.
std::optional<CachedHeader> cached_header(const SceneCacheRecord& record) {
  const auto file_name = record.get("file_name"), name = record.get("namespace"), text = record.get("text");
  const auto before = record.get("operations_before_cse"), after = record.get("operations_after_cse");
  const auto jacobian_name = record.get("jacobian");
  if (!file_name || !name || !text || !before || !after || !jacobian_name) return std::nullopt;
  const std::optional<JacobianKind> jacobian = parse_jacobian_kind(*jacobian_name);
  const std::optional<OperationCount> before_cse = parse_count(*before), after_cse = parse_count(*after);
  if (!jacobian || !before_cse || !after_cse) return std::nullopt;
  return CachedHeader{{*file_name, *name, *text, *before_cse, *after_cse}, *jacobian};
}

}  // namespace

std::string to_string(Backend backend) {
  switch (backend) {
    case Backend::compiled:
      return "compiled";
    case Backend::interpreted:
      return "interpreted";
    case Backend::automatic:
      return "auto";
  }
  return "compiled";
}

std::optional<Backend> parse_backend(const std::string& name) {
  for (Backend b : {Backend::compiled, Backend::interpreted, Backend::automatic})
    if (name == to_string(b)) return b;
  return std::nullopt;
}

LoadedModel::LoadedModel(ModelKind kind, JacobianKind jacobian, GeneratedHeader header, CompiledLibrary library,
                         runtime::Model model, BuildTimings timings)
    : kind_(kind),
      jacobian_(jacobian),
      header_(std::move(header)),
      library_(std::move(library)),
      model_(std::move(model)),
      timings_(timings) {}

LoadedModel load_header(const GeneratedHeader& header, ModelKind kind, JacobianKind jacobian,
                        const CompileOptions& options) {
  BuildTimings timings;
  const auto start = base::Clock::now();
  // The table must name the scene and model the header was generated for.
  auto [library, model] = compile_and_load(header.text, header.namespace_name, identity_of(header, kind), options);
  timings.compile = library.seconds;
  timings.load = std::max(0.0, base::seconds_since(start) - library.seconds);
  return LoadedModel(kind, jacobian, header, std::move(library), std::move(model), timings);
}

void remember_compiled_header(const Scene& scene, ModelKind kind, const BuildOptions& options,
                              const GeneratedHeader& header, JacobianKind jacobian,
                              const std::filesystem::path& library_directory) {
  if (!options.scene_cache || !scene_cache_enabled()) return;
  // The key of a compiled build: what build() looks up first.
  BuildOptions compiled = options;
  compiled.backend = Backend::compiled;
  if (const std::optional<std::string> key =
          scene_cache_key(scene, kHeaderProduct, header_options_text(scene, kind, compiled), scene_cache_version(),
                          FingerprintScope::equations))
    SceneCache(library_directory, options.compile.warn).store(*key, header_record(header, jacobian));
}

namespace {

constexpr const char* kProgramProduct = "interpreted program";

/// The scene cache's key of `product` build() may take from there; none when the cache is off.
std::optional<std::string> product_key(const Scene& scene, ModelKind kind, const BuildOptions& options,
                                       const char* product) {
  if (!options.scene_cache || !scene_cache_enabled()) return std::nullopt;
  return scene_cache_key(scene, product, header_options_text(scene, kind, options), scene_cache_version(),
                         FingerprintScope::equations);
}

/// The key of the compiled model's header: none interpreted, whose model needs the program.
std::optional<std::string> header_key(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  if (options.backend == Backend::interpreted) return std::nullopt;
  return product_key(scene, kind, options, kHeaderProduct);
}

/// The key of the interpreted model's program: none for a compiled build.
std::optional<std::string> program_key(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  if (options.backend == Backend::compiled) return std::nullopt;
  return product_key(scene, kind, options, kProgramProduct);
}

}  // namespace

class SceneCacheHit {
 public:
  CachedHeader header;
  /// Interpreted: the program read back (checked); null: the header is compiled's.
  std::shared_ptr<const InterpretedProgram> program;
};

BuildLookup look_up_build(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  const auto start = base::Clock::now();
  BuildLookup lookup;
  const SceneCache cache(options.compile.cache_directory, options.compile.warn);
  if (const std::optional<std::string> key = header_key(scene, kind, options))
    if (const std::optional<SceneCacheRecord> record = cache.load(*key))
      if (std::optional<CachedHeader> header = cached_header(*record))
        lookup.hit = std::make_shared<SceneCacheHit>(SceneCacheHit{std::move(*header), nullptr});
  if (!lookup.hit)
    if (const std::optional<std::string> key = program_key(scene, kind, options))
      if (const std::optional<SceneCacheRecord> record = cache.load(*key)) {
        std::optional<CachedHeader> header = cached_header(*record);
        const std::optional<std::string> bytes = record->get("program");
        std::shared_ptr<const InterpretedProgram> program =
            header && bytes ? interpreted_program_from_bytes(*bytes, scene.name, to_string(kind)) : nullptr;
        if (program)
          lookup.hit = std::make_shared<SceneCacheHit>(SceneCacheHit{std::move(*header), std::move(program)});
        else cache.discard(*key, "its interpreted program is not one nhc can run (damaged or foreign)");
      }
  lookup.seconds = base::seconds_since(start);
  return lookup;
}

bool build_derives(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  return look_up_build(scene, kind, options).derives();
}

LoadedModel build(const Scene& scene, ModelKind kind, const BuildOptions& options, const DerivedAndAnalysed* given) {
  return build(scene, kind, options, given, look_up_build(scene, kind, options));
}

LoadedModel build(const Scene& scene, ModelKind kind, const BuildOptions& options, const DerivedAndAnalysed* given,
                  const BuildLookup& lookup) {
  // The scene cache first: an unchanged scene skips derive, reduce and generate.
  const double lookup_seconds = lookup.seconds;
  if (const SceneCacheHit* hit = lookup.hit.get()) {
    if (hit->program) {  // interpreted before: nothing is lowered either
      const auto start = base::Clock::now();
      runtime::Model model = interpret(hit->program);
      BuildTimings timings;
      timings.scene_cache = lookup_seconds;
      timings.scene_cached = true;
      timings.interpreted = true;
      timings.load = base::seconds_since(start);
      return LoadedModel(kind, hit->header.jacobian, hit->header.header, CompiledLibrary{}, std::move(model), timings);
    }
    LoadedModel loaded = load_header(hit->header.header, kind, hit->header.jacobian, options.compile);
    BuildTimings timings = loaded.timings();
    timings.scene_cache = lookup_seconds;
    timings.scene_cached = true;
    return LoadedModel(kind, hit->header.jacobian, hit->header.header, loaded.library(), runtime::Model(loaded.model()),
                       timings);
  }

  auto start = base::Clock::now();
  // Derived once: from the preparation (with its analysis) when given, else here.
  std::optional<DerivedModel> derived_here;
  if (!given) derived_here = derive_model(scene, kind);
  const DerivedModel& derived = given ? given->derived : *derived_here;
  const Index1System system = [&] {
    if (given) {
      if (given->structure.system.model != kind) throw std::logic_error("jit::build: the analysis is of another model");
      return reduce_to_index1(scene, given->structure);
    }
    if (!derived.applicable)
      throw MathError("the " + to_string(kind) + " model does not apply to " + scene.name + ": " + derived.reason);
    check_for_stop_now();
    return reduce_to_index1(scene, derived);
  }();
  check_for_stop_now();
  // The multiplier-free form where the model has one (docs/reduced-form.md), on the default speeds.
  std::optional<ReducedForm> reduced;
  if (options.reduced_form) reduced = reduce_to_independent_speeds(scene, derived);
  const double derive_seconds = base::seconds_since(start);

  start = base::Clock::now();
  HeaderOptions header_options;
  header_options.jacobian = options.jacobian.value_or(default_jacobian_kind(system.size()));
  header_options.sensitivities = options.sensitivities;
  header_options.variational = options.variational;
  header_options.split_from_bytes = options.split_from_bytes;
  header_options.reduced = reduced ? &*reduced : nullptr;
  const bool may_interpret = options.backend != Backend::compiled;
  PreparedModel prepared;
  GeneratedHeader header = generate_header(scene, system, header_options, may_interpret ? &prepared : nullptr);
  check_for_stop_now();
  const double generate_seconds = base::seconds_since(start);

  if (may_interpret && interpretable(prepared)) {
    start = base::Clock::now();
    const std::shared_ptr<const InterpretedProgram> program = interpreted_program(scene, system, prepared);
    runtime::Model model = interpret(program);
    BuildTimings timings;
    timings.derive = derive_seconds;
    timings.generate = generate_seconds;
    timings.load = base::seconds_since(start);
    // Stored once the model is made, so that the next run neither derives nor lowers.
    start = base::Clock::now();
    if (const std::optional<std::string> key = program_key(scene, kind, options)) {
      SceneCacheRecord record = header_record(header, header_options.jacobian);
      record.set("program", to_bytes(*program));
      SceneCache(options.compile.cache_directory, options.compile.warn).store(*key, record);
    }
    timings.scene_cache = lookup_seconds + base::seconds_since(start);
    timings.interpreted = true;
    return LoadedModel(kind, header_options.jacobian, std::move(header), CompiledLibrary{}, std::move(model), timings);
  }
  if (options.backend == Backend::interpreted)
    throw MathError("the " + to_string(kind) + " model of " + scene.name +
                    " has a function the interpreter does not run: use --backend compiled");

  LoadedModel loaded = load_header(header, kind, header_options.jacobian, options.compile);
  // Stored once the header compiled and loaded, beside the library (the compile cache's checked
  // directory): a refused or interrupted build leaves no entry.
  start = base::Clock::now();
  if (const std::optional<std::string> key = header_key(scene, kind, options))
    SceneCache(loaded.library().path.parent_path(), options.compile.warn)
        .store(*key, header_record(header, header_options.jacobian));
  const double store_seconds = base::seconds_since(start);
  BuildTimings timings = loaded.timings();
  timings.derive = derive_seconds;
  timings.generate = generate_seconds;
  timings.scene_cache = lookup_seconds + store_seconds;
  return LoadedModel(kind, header_options.jacobian, std::move(header), loaded.library(), runtime::Model(loaded.model()),
                     timings);
}

}  // namespace nhc::jit
