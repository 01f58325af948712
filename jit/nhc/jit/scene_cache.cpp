// The scene-level cache: verified entries of what the symbolic pipeline made of a scene (scene_cache.hpp).
#include "nhc/jit/scene_cache.hpp"

#include "nhc/jit/generator_fingerprint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/jit/cache_size.hpp"
#include "nhc/tools/sha256.hpp"

namespace nhc::jit {

namespace fs = std::filesystem;
using tools::sha256_hex;

namespace {

constexpr const char* kEntryMagic = "nhc scene cache entry 1";

/// A double exactly, in C99 hexadecimal notation.
std::string exact(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

/// `text` preceded by its length: fields of any content cannot run into each other.
std::string counted(const std::string& text) { return std::to_string(text.size()) + ":" + text; }

bool is_hex_digest(const std::string& text) {
  if (text.size() != 64) return false;
  for (char c : text)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

/// Reads the line starting at `pos` (without its '\n'); false when there is no '\n'.
bool read_line(const std::string& bytes, std::size_t& pos, std::string& line) {
  const std::size_t end = bytes.find('\n', pos);
  if (end == std::string::npos) return false;
  line = bytes.substr(pos, end - pos);
  pos = end + 1;
  return true;
}

/// A non-negative decimal number, all of `text`, below 2^40.
std::optional<std::size_t> parse_size(const std::string& text) {
  if (text.empty() || text.size() > 13) return std::nullopt;
  std::size_t value = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<std::size_t>(c - '0');
  }
  return value;
}

/// The entry's bytes, opened without following a link and checked on the open file: a regular
/// file owned by the user and writable by no one else. nullopt with `problem` set otherwise.
std::optional<std::string> read_private_file(const fs::path& path, std::string& problem) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    problem = errno == ELOOP ? "it is a symbolic link" : std::strerror(errno);
    return std::nullopt;
  }
  struct stat st {};
  std::string bytes;
  if (::fstat(fd, &st) != 0) {
    problem = std::strerror(errno);
  } else if (!S_ISREG(st.st_mode)) {
    problem = "not a regular file";
  } else if (st.st_uid != ::geteuid()) {
    problem = "owned by user id " + std::to_string(st.st_uid) + ", not by you";
  } else if (st.st_mode & (S_IWGRP | S_IWOTH)) {
    problem = "writable by others";
  } else {
    char buffer[1 << 16];
    for (;;) {
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) problem = std::strerror(errno);
      if (n <= 0) break;
      bytes.append(buffer, static_cast<std::size_t>(n));
    }
  }
  ::close(fd);
  if (!problem.empty()) return std::nullopt;
  return bytes;
}

/// The payload of an entry's bytes when its header names `key` and the payload's length and
/// SHA-256; nullopt with `problem` set otherwise.
std::optional<std::string> checked_payload(const std::string& bytes, const std::string& key, std::string& problem) {
  std::size_t pos = 0;
  std::string magic, key_line, digest_line, size_line;
  if (!read_line(bytes, pos, magic) || magic != kEntryMagic || !read_line(bytes, pos, key_line) ||
      !read_line(bytes, pos, digest_line) || !read_line(bytes, pos, size_line)) {
    problem = "not a scene cache entry (damaged)";
    return std::nullopt;
  }
  if (key_line != "key " + key) {
    problem = "it holds another key";
    return std::nullopt;
  }
  const std::optional<std::size_t> size =
      size_line.rfind("bytes ", 0) == 0 ? parse_size(size_line.substr(6)) : std::nullopt;
  if (digest_line.rfind("sha256 ", 0) != 0 || !is_hex_digest(digest_line.substr(7)) || !size) {
    problem = "not a scene cache entry (damaged)";
    return std::nullopt;
  }
  const std::size_t expected = size.value_or(0);
  if (bytes.size() - pos != expected) {
    problem = "its payload has " + std::to_string(bytes.size() - pos) + " bytes, not " + std::to_string(expected) +
              " (truncated or damaged)";
    return std::nullopt;
  }
  std::string payload = bytes.substr(pos);
  if (sha256_hex(payload) != digest_line.substr(7)) {
    problem = "its payload does not match its SHA-256 digest (damaged or replaced)";
    return std::nullopt;
  }
  return payload;
}

Warning default_warning() {
  return [](const std::string& line) { std::cerr << "nhc: warning: " << line << std::endl; };
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// SceneCacheRecord: "<name> <length>\n<value>\n" per field, in name order.

std::optional<std::string> SceneCacheRecord::get(const std::string& name) const {
  const auto it = fields_.find(name);
  if (it == fields_.end()) return std::nullopt;
  return it->second;
}

std::string SceneCacheRecord::serialize() const {
  std::string out;
  for (const auto& [name, value] : fields_) out += name + " " + std::to_string(value.size()) + "\n" + value + "\n";
  return out;
}

std::optional<SceneCacheRecord> SceneCacheRecord::parse(const std::string& bytes) {
  SceneCacheRecord record;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    std::string line;
    if (!read_line(bytes, pos, line)) return std::nullopt;
    const std::size_t space = line.rfind(' ');
    if (space == std::string::npos || space == 0) return std::nullopt;
    const std::optional<std::size_t> size = parse_size(line.substr(space + 1));
    if (!size || bytes.size() - pos < *size + 1 || bytes[pos + *size] != '\n') return std::nullopt;
    record.fields_[line.substr(0, space)] = bytes.substr(pos, *size);
    pos += *size + 1;
  }
  return record;
}

// ---------------------------------------------------------------------------------------------
// Keys

namespace {

/// The system's fingerprint with its text whole (`whole_text`) or as equations_source() keeps it.
std::optional<std::string> fingerprint_of(const SceneSystem& system, bool whole_text) {
  const std::string& text = system.source_text();
  if (text.empty()) return std::nullopt;
  std::ostringstream out;
  if (whole_text) out << "source " << counted(text) << "\n";
  else out << "text " << counted(equations_source(text)) << "\n";
  out << "file " << counted(fs::path(system.source_path).filename().string()) << "\n";
  out << "name " << counted(system.name) << "\n";
  out << "definitions " << (system.keep_definitions ? "kept" : "substituted") << "\n";
  out << "models";
  for (ModelKind kind : system.models) out << " " << to_string(kind);
  out << "\ndependent";
  for (int d : system.dependent) out << " " << d;
  out << "\n";
  return out.str();
}

}  // namespace

std::optional<std::string> system_fingerprint(const SceneSystem& system) { return fingerprint_of(system, false); }

std::optional<std::string> scene_fingerprint(const Scene& scene, FingerprintScope scope) {
  const bool everything = scope == FingerprintScope::everything;
  // Everything: the whole text, which holds the equations' text (and spares parsing it again).
  const std::optional<std::string> system = fingerprint_of(scene, everything);
  if (!system) return std::nullopt;
  std::ostringstream out;
  out << "scope " << (everything ? "everything" : "equations") << "\n" << *system;
  out << "parameters";
  for (double v : scene.parameter_values) out << " " << exact(v);
  out << "\n";
  if (everything) {
    out << "initial t0 " << exact(scene.initial.t0) << "\n";
    for (const auto& [name, values] : scene.initial.values) {
      out << "initial " << counted(name);
      for (double v : values) out << " " << exact(v);
      out << "\n";
    }
    out << "fixed";
    for (const std::string& name : scene.initial.fixed) out << " " << counted(name);
    out << "\nsimulate model " << (scene.simulate.model ? to_string(*scene.simulate.model) : "-") << " t_end "
        << exact(scene.simulate.t_end) << " rtol " << exact(scene.simulate.rtol) << " atol "
        << exact(scene.simulate.atol) << " outputs "
        << (scene.simulate.outputs ? std::to_string(*scene.simulate.outputs) : "-") << "\n";
  }
  return out.str();
}

std::string scene_cache_version() { return std::string(NHC_VERSION) + ", generator " + NHC_GENERATOR_FINGERPRINT; }

std::optional<std::string> scene_cache_key(const Scene& scene, const std::string& product, const std::string& options,
                                           const std::string& version, FingerprintScope scope) {
  const std::optional<std::string> fingerprint = scene_fingerprint(scene, scope);
  if (!fingerprint) return std::nullopt;
  return sha256_hex("nhc scene cache\nversion " + counted(version) + "\nproduct " + counted(product) + "\noptions " +
                    counted(options) + "\n" + *fingerprint);
}

bool scene_cache_enabled() {
  const char* setting = std::getenv("NHC_SCENE_CACHE");
  if (!setting) return true;
  const std::string value = setting;
  return !(value == "off" || value == "0");
}

// ---------------------------------------------------------------------------------------------
// SceneCache

SceneCache::SceneCache(fs::path cache_directory, Warning warn)
    : requested_(std::move(cache_directory)), warn_(warn ? std::move(warn) : default_warning()) {}

fs::path SceneCache::entry_path(const std::string& key) const {
  if (entries_.empty()) {
    const fs::path base = requested_.empty() ? private_cache_directory(default_cache_location(), warn_)
                                             : private_cache_directory({requested_, false}, warn_);
    entries_ = private_cache_directory({base / "scenes", false}, warn_);
  }
  return entries_ / (key + ".entry");
}

std::optional<SceneCacheRecord> SceneCache::load(const std::string& key) const {
  // No scenes directory where the cache would be: nothing to find, and nothing is created.
  std::error_code ec;
  const fs::path base = requested_.empty() ? default_cache_location().path : requested_;
  if (entries_.empty() && !fs::exists(fs::symlink_status(base / "scenes", ec))) return std::nullopt;
  const fs::path path = entry_path(key);  // the directories checked before anything in them is read
  if (!fs::exists(fs::symlink_status(path, ec))) return std::nullopt;
  std::string problem;
  std::optional<SceneCacheRecord> record;
  if (const std::optional<std::string> bytes = read_private_file(path, problem))
    if (const std::optional<std::string> payload = checked_payload(*bytes, key, problem)) {
      record = SceneCacheRecord::parse(*payload);
      if (!record) problem = "its payload is not a record (damaged)";
    }
  if (record) {
    mark_used(path);
    return record;
  }
  warn_("scene cache entry " + path.string() + " rejected: " + problem + "; rebuilding it");
  ::unlink(path.c_str());
  return std::nullopt;
}

void SceneCache::discard(const std::string& key, const std::string& problem) const {
  const fs::path path = entry_path(key);
  warn_("scene cache entry " + path.string() + " rejected: " + problem + "; rebuilding it");
  ::unlink(path.c_str());
}

void SceneCache::store(const std::string& key, const SceneCacheRecord& record) const {
  const fs::path path = entry_path(key);
  const std::string payload = record.serialize();
  const std::string bytes = std::string(kEntryMagic) + "\nkey " + key + "\nsha256 " + sha256_hex(payload) + "\nbytes " +
                            std::to_string(payload.size()) + "\n" + payload;
  // A name unique to this process and call, registered before it exists (temporary_files.hpp);
  // concurrent runs write the same bytes and rename them into place, either one wins.
  const TemporaryFile temporary(unique_temporary_name(path.string()));
  errno = 0;
  {
    std::ofstream file(temporary.path(), std::ios::binary);
    file << bytes;
    file.close();
    if (!file) {
      warn_("cannot store the scene cache entry " + path.string() + ": " +
            (errno ? std::strerror(errno) : "write failed") + " (the run goes on without it)");
      return;
    }
  }
  ::chmod(temporary.path().c_str(), 0600);
  if (std::rename(temporary.path().c_str(), path.c_str()) != 0) {
    warn_("cannot store the scene cache entry " + path.string() + ": " + std::strerror(errno) +
          " (the run goes on without it)");
    return;
  }
  evict_over_limit(entries_.parent_path(), path);
}

}  // namespace nhc::jit
