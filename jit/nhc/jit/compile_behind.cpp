#include "nhc/jit/compile_behind.hpp"

#include <algorithm>
#include <iostream>

#include "nhc/errors.hpp"
#include "nhc/jit/interpreted_model.hpp"

namespace nhc::jit {

double predicted_compile_seconds(const GeneratedHeader& header, const CompileOptions& options) {
  const std::vector<std::string> flags = optimization_flags(options, header.text.size());
  const bool optimized = std::find(flags.begin(), flags.end(), "-O0") == flags.end();
  return 0.3 + (optimized ? 20.0 : 3.0) * static_cast<double>(header.text.size()) / 1e6;
}

CompileBehind::CompileBehind(const Scene& scene, ModelKind kind, const BuildOptions& options, const LoadedModel& loaded)
    : scene_(scene), kind_(kind), options_(options), loaded_(loaded) {
  active_ = loaded.timings().interpreted && options.backend == Backend::automatic;
  if (active_)
    predicted_seconds_ =
        options.compile_behind_after.value_or(predicted_compile_seconds(loaded.header(), options.compile));
}

CompileBehind::~CompileBehind() {
  // A run that failed still waits for its compile: the thread must not outlive what it reads.
  if (compile_.valid()) compile_.wait();
}

bool CompileBehind::poll() {
  if (!active_ || switched_) return switched_;
  if (!compile_.valid()) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (elapsed < predicted_seconds_) return false;
    const GeneratedHeader& header = loaded_.header();
    const ModelIdentity identity{scene_.name, to_string(kind_)};
    compile_ = std::async(std::launch::async, [header, identity, options = options_.compile] {
      return compile_and_load(header.text, header.namespace_name, identity, options);
    });
    return false;
  }
  if (compile_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
  try {
    compiled_ = compile_.get();
  } catch (const std::exception& e) {
    std::cerr << "nhc: warning: compiling behind the interpreted run failed, it goes on interpreted: " << e.what()
              << "\n";
    active_ = false;
    return false;
  }
  switched_ = adopt_compiled(loaded_.model(), compiled_->second);
  return switched_;
}

bool CompileBehind::finish() {
  if (!active_) return false;
  if (compile_.valid()) {
    compile_.wait();
    poll();
  }
  if (!compiled_ || recorded_) return compiled_.has_value();
  remember_compiled_header(scene_, kind_, options_, loaded_.header(), loaded_.jacobian(),
                           compiled_->first.path.parent_path());
  recorded_ = true;
  return true;
}

}  // namespace nhc::jit
