#pragma once
/// \file compiler.hpp
/// \brief Compiling a model header (generated, or hand-written against the C table of
/// nhc/runtime/model_table.h) into a shared object in the compile cache, and loading it.

#include <filesystem>
#include <string>
#include <vector>

#include "nhc/runtime/model.hpp"

namespace nhc::jit {

/// How a header becomes a shared object.
struct CompileOptions {
  /// The C++ compiler; empty: the one that built nhc.
  std::string compiler;
  /// Optimization and extra flags; the flags the contract needs (-std=c++17 -fPIC -shared,
  /// hidden visibility) are always added.
  std::vector<std::string> flags{"-O2"};
  /// Extra include directories (-I), searched before the one that provides
  /// nhc/runtime/model_table.h (always added: hand-written headers include it).
  std::vector<std::filesystem::path> include_directories;
  /// Empty: default_cache_directory().
  std::filesystem::path cache_directory;
};

/// `$NHC_CACHE_DIR`, else `$XDG_CACHE_HOME/nhc`, else `~/.cache/nhc`, else a directory of the
/// user's own under the temporary directory.
std::filesystem::path default_cache_directory();

/// A shared object built from a header, and whether the cache already held it.
struct CompiledLibrary {
  std::filesystem::path path;
  bool reused = false;
  double seconds = 0;  ///< compiling (or finding it in the cache)
};

/// Compiles `header_text` (a complete model header defining one model table) into a shared
/// object exporting only `nhc_model_table_get`, or reuses the cached one. `label` names the
/// header in messages and the cache entry (a C++ identifier, e.g. the generated namespace).
/// Throws std::runtime_error with the compiler's output when it fails.
CompiledLibrary compile_header(const std::string& header_text, const std::string& label,
                               const CompileOptions& options = {});

/// A header file on disk (e.g. a hand-written model), compiled as compile_header() does, with
/// its own directory on the include path.
CompiledLibrary compile_header_file(const std::filesystem::path& header, const CompileOptions& options = {});

}  // namespace nhc::jit
