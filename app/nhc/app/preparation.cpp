#include "nhc/app/preparation.hpp"

#include <chrono>

#include "nhc/app/switched_run.hpp"
#include "nhc/errors.hpp"
#include "nhc/jit/scene_cache.hpp"

namespace nhc::app {

const ModelAnalysis& Preparation::analysis(const InitializationOptions& options) {
  if (!analysis_) {
    derived_ = derive_model(scene_, kind_);
    analysis_ = analyze_model(scene_, *derived_, options);
  }
  return *analysis_;
}

const StructuralAnalysis* Preparation::structure() const noexcept {
  if (!analysis_ || !analysis_->structure || analysis_->structure->structurally_singular) return nullptr;
  return &*analysis_->structure;
}

jit::LoadedModel Preparation::build(const Scene& scene, const jit::BuildOptions& options) const {
  return build(scene, options, jit::look_up_build(scene, kind_, options));
}

jit::LoadedModel Preparation::build(const Scene& scene, const jit::BuildOptions& options,
                                    const jit::BuildLookup& lookup) const {
  const StructuralAnalysis* analysed = structure();
  if (!analysed) return jit::build(scene, kind_, options, nullptr, lookup);
  const jit::DerivedAndAnalysed given{*derived_, *analysed};
  return jit::build(scene, kind_, options, &given, lookup);
}

InitialPointCheck check_initial_point(Preparation& preparation, bool repair) {
  const Scene& scene = preparation.scene();
  const ModelKind kind = preparation.kind();
  InitialPointCheck check;
  if (jit::scene_cache_enabled())
    check.key = jit::scene_cache_key(scene, "initial point check",
                                     "model " + to_string(kind) + ", repair " + (repair ? "yes" : "no"));
  if (check.key)
    if (const std::optional<jit::SceneCacheRecord> record = jit::SceneCache().load(*check.key))
      check.cached = record->get("outcome") == std::string("passed");
  if (check.cached) return check;
  InitializationOptions init;
  init.repair = repair;
  const ModelAnalysis& a = preparation.analysis(init);
  if (!a.initial_values_repairable) {
    check.problems_at_t0 = a.errors;
    return check;
  }
  std::string message;
  for (const std::string& e : a.errors) message += (message.empty() ? "" : "\nnhc: error: ") + e;
  throw MathError(message);
}

void remember_check(const InitialPointCheck& check, const jit::LoadedModel& built) {
  // A point with problems is analysed again by every run, so that a failure there gets its words.
  if (!check.key || check.cached || !check.problems_at_t0.empty()) return;
  jit::SceneCacheRecord record;
  record.set("outcome", "passed");
  jit::SceneCache(built.library().path.parent_path()).store(*check.key, record);
}

PreparedModel prepare_and_build(Preparation& preparation, const Scene& written, bool repair,
                                const jit::BuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  InitialPointCheck check =
      sliding_contact(preparation.scene()) ? InitialPointCheck{} : check_initial_point(preparation, repair);
  // A check found cached skipped the analysis; a build that derives then makes it here, so that it
  // derives after the same analysis as on a cold cache: the analysis makes symbols, and GiNaC
  // orders terms by symbol hash, which follows creation order (the model would otherwise depend on
  // what the cache holds).
  // The cache is looked up once: the entry that decides here is the one the build takes (an
  // entry rejected between the two would leave a build that derives without the analysis).
  const jit::BuildLookup lookup = jit::look_up_build(written, preparation.kind(), options);
  if (check.cached && lookup.derives()) {
    InitializationOptions init;
    init.repair = repair;
    preparation.analysis(init);
  }
  // The lookup's time is the build's (BuildTimings::scene_cache), not the check's.
  const double check_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - lookup.seconds;
  jit::LoadedModel built = preparation.build(written, options, lookup);
  remember_check(check, built);
  return PreparedModel{std::move(check), check_seconds, std::move(built)};
}

}  // namespace nhc::app
