// A scene's model derived, generated, compiled and loaded (build.hpp).
#include "nhc/jit/build.hpp"

#include <chrono>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"

namespace nhc::jit {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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
  CompiledLibrary library = compile_header(header.text, header.namespace_name, options);
  timings.compile = library.seconds;
  const auto load_start = Clock::now();
  runtime::Model model = runtime::Model::load(library.path.string());
  timings.load = seconds_since(load_start);
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
