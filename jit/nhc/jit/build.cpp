// A scene's model derived, generated, compiled and loaded (build.hpp).
#include "nhc/jit/build.hpp"

#include <algorithm>
#include <chrono>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"

namespace nhc::jit {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// The scene and model a generated header is for: its namespace is `<scene>_<model>`
/// (header_emitter.hpp). A header named otherwise (written by hand) has its model checked only.
ModelIdentity identity_of(const GeneratedHeader& header, ModelKind kind) {
  const std::string model = to_string(kind), suffix = "_" + model;
  const std::string& name = header.namespace_name;
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    return {name.substr(0, name.size() - suffix.size()), model};
  return {"", model};
}

}  // namespace

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
  const auto start = Clock::now();
  // The table must name the scene and model the header was generated for.
  auto [library, model] = compile_and_load(header.text, header.namespace_name,
                                           identity_of(header, kind), options);
  timings.compile = library.seconds;
  timings.load = std::max(0.0, seconds_since(start) - library.seconds);
  return LoadedModel(kind, jacobian, header, std::move(library), std::move(model), timings);
}

LoadedModel build(const Scene& scene, ModelKind kind, const BuildOptions& options) {
  auto start = Clock::now();
  const DerivedModel derived = derive_model(scene, kind);
  if (!derived.applicable)
    throw MathError("the " + to_string(kind) + " model does not apply to " + scene.name + ": " + derived.reason);
  const Index1System system = reduce_to_index1(scene, derived);
  const double derive_seconds = seconds_since(start);

  start = Clock::now();
  HeaderOptions header_options;
  header_options.jacobian = options.jacobian.value_or(default_jacobian_kind(system.size()));
  header_options.sensitivities = options.sensitivities;
  GeneratedHeader header = generate_header(scene, system, header_options);
  const double generate_seconds = seconds_since(start);

  LoadedModel loaded = load_header(header, kind, header_options.jacobian, options.compile);
  BuildTimings timings = loaded.timings();
  timings.derive = derive_seconds;
  timings.generate = generate_seconds;
  return LoadedModel(kind, header_options.jacobian, std::move(header), loaded.library(),
                     runtime::Model(loaded.model()), timings);
}

}  // namespace nhc::jit
