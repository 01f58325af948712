#pragma once
/// \file cache.hpp
/// \brief The compile cache: a private directory (the rules of ccache and OpenSSH) of shared
/// objects, each with a sidecar `<entry>.so.sha256` (sha256sum format) holding the digest of its
/// bytes, checked before the library is opened.
///
/// A shared object runs code when it is loaded (its constructors), so an entry is trusted only
/// when the directory can be written by the user alone and the entry's bytes are the ones this
/// user's nhc wrote. Whatever fails a check is a cache miss: the entry is rebuilt.

#include <filesystem>
#include <functional>
#include <string>

namespace nhc::jit {

using Warning = std::function<void(const std::string&)>;

/// Where the cache is by default, and whether it is the shared temporary directory's fallback.
struct CacheLocation {
  std::filesystem::path path;
  bool temporary_fallback = false;
};

/// `$NHC_CACHE_DIR`, else `$XDG_CACHE_HOME/nhc`, else `$HOME/.cache/nhc`, else
/// `$TMPDIR/nhc-cache-<uid>` (the fallback).
CacheLocation default_cache_location();

/// The cache directory, created 0700 when missing (its parents with the usual mode). Refused
/// with EnvironmentError (exit 4) when it is not a directory, not owned by the user, or writable
/// by group or others. The temporary-directory fallback is never refused and never used when it
/// fails these checks (anyone can create it first): a fresh private directory beside it is used
/// instead, with a warning.
std::filesystem::path private_cache_directory(const CacheLocation& location, const Warning& warn);

/// Why the entry `library` must not be used; empty when it is sound: a regular file (not a
/// symbolic link) owned by the user, writable by no one else, whose sidecar digest matches its
/// bytes. Call only when `library` exists.
std::string entry_problem(const std::filesystem::path& library);

/// The sidecar of `library`: `library` + ".sha256".
std::filesystem::path digest_path(const std::filesystem::path& library);

/// The sidecar's text for a library file named `file_name` with digest `sha256`.
std::string digest_text(const std::string& sha256, const std::string& file_name);

/// Removes the entry and its sidecar (a damaged or foreign entry before it is rebuilt).
void discard_entry(const std::filesystem::path& library) noexcept;

}  // namespace nhc::jit
