#pragma once
/// \file scene_cache.hpp
/// \brief The scene-level cache: what the symbolic pipeline (derive, analyze, generate) made of
/// an unchanged scene, so that running it again skips the pipeline. Beside the compile cache
/// (cache.hpp), in its `scenes/` subdirectory, under the same rules: a private directory, one
/// file per entry written to a temporary name and renamed (concurrent runs write the same bytes),
/// every entry checked (a regular file owned by the user and writable by no one else, its key and
/// the SHA-256 of its payload recorded in it and matching) before anything in it is used. An entry
/// failing a check is a miss: it is removed with a one-line warning and rebuilt, never trusted.
///
/// The key of an entry is the SHA-256 of nhc's version, the product's name (what the entry holds),
/// the product's options in words, and the scene's fingerprint: the system's (system_fingerprint)
/// and the experiment's values the product depends on, written as numbers. The generated header
/// is keyed by what it is made from (FingerprintScope::equations): the system and the parameter
/// values (its defaults), not the initial data or run settings, which it takes at run time, so a
/// new start or tolerance reuses it (and the compile cache its library), except that a header with
/// the multiplier-free form is keyed also by the speeds chosen at the start (jit/build.cpp,
/// docs/reduced-form.md); the initial-point check keeps the key of everything. The system's fingerprint is made from
/// the text it was read from, which stands for it only while none of its fields has changed
/// (SceneSystem::source_text()): a system assembled or changed in code has none and is never cached. SceneBuilder's
/// scenes have the text they are built from.

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "nhc/jit/cache.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::jit {

/// Named text fields: the payload of one entry (serialized with lengths, so any bytes round-trip).
class SceneCacheRecord {
 public:
  void set(const std::string& name, std::string value) { fields_[name] = std::move(value); }
  /// The field, or nullopt when the record lacks it.
  std::optional<std::string> get(const std::string& name) const;

  std::string serialize() const;
  /// nullopt when `bytes` is not a serialized record.
  static std::optional<SceneCacheRecord> parse(const std::string& bytes);

 private:
  std::map<std::string, std::string> fields_;
};

/// What of a scene a product depends on.
enum class FingerprintScope {
  /// Everything: the text and every value code may change (an initial-point check).
  everything,
  /// What the equations and the header are made from: the system (system_fingerprint()) and the
  /// parameter values (the header's defaults); not the initial data and run settings, which the
  /// header takes at run time. A new start or tolerance finds the same header.
  equations,
};

/// The system's fingerprint: the text it was read from without the tables of the experiment and
/// the presentation (equations_source()), its file's name (the generated banner names it), its
/// name, and the definitions' form (SceneOptions, not in the text); nullopt for a system without
/// source text (assembled, or changed in code since it was read). A function of the system
/// alone: no change of the experiment or the presentation reaches it.
std::optional<std::string> system_fingerprint(const SceneSystem& system);

/// The scene's fingerprint (see the file comment): the system's, the parameter values, and for
/// FingerprintScope::everything the whole text, initial data and settings; nullopt for a scene
/// without source text.
std::optional<std::string> scene_fingerprint(const Scene& scene, FingerprintScope scope = FingerprintScope::everything);

/// What made the products: NHC_VERSION and the SHA-256 of the code generator's sources (a build
/// from other sources of the same version derives again instead of reusing what it did not make).
std::string scene_cache_version();

/// The key of `product` of `scene` with `options` (words naming every option the product depends
/// on) under nhc `version`: 64 hexadecimal digits; nullopt for a scene without source text.
std::optional<std::string> scene_cache_key(const Scene& scene, const std::string& product, const std::string& options,
                                           const std::string& version = scene_cache_version(),
                                           FingerprintScope scope = FingerprintScope::everything);

/// False when `$NHC_SCENE_CACHE` is `off` (or `0`): every product is derived again and nothing is
/// stored (the compile cache still applies).
bool scene_cache_enabled();

/// The entries under one cache directory.
class SceneCache {
 public:
  /// `cache_directory`: the compile cache's directory (empty: default_cache_location()); the
  /// entries live in its `scenes/` subdirectory, created and checked on first use. `warn`
  /// receives the one-line warnings (empty: standard error, as `nhc: warning: …`).
  explicit SceneCache(std::filesystem::path cache_directory = {}, Warning warn = {});

  /// The record stored under `key`; nullopt when there is none, or when the entry fails a check
  /// (then it is removed, with a warning). Creates nothing: a run refused later leaves no cache.
  std::optional<SceneCacheRecord> load(const std::string& key) const;
  /// Stores `record` under `key` (written to a temporary name and renamed); call it once the
  /// product has been used successfully (compiled, loaded). A failure to write is a warning, not
  /// an error: the run goes on without the entry.
  void store(const std::string& key, const SceneCacheRecord& record) const;

  /// Removes the entry under `key`, which passed the file's checks but not its reader's
  /// (`problem`: what is wrong with it), with the same warning as a damaged entry.
  void discard(const std::string& key, const std::string& problem) const;

  /// The file of the entry under `key` (whether or not it exists); creates and checks the
  /// directories (private_cache_directory()).
  std::filesystem::path entry_path(const std::string& key) const;

 private:
  std::filesystem::path requested_;
  Warning warn_;
  mutable std::filesystem::path entries_;  // resolved on first use
};

}  // namespace nhc::jit
