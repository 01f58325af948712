#pragma once
/// \file compiler.hpp
/// \brief Compiling a model header (generated, or hand-written against the C table of
/// nhc/runtime/model_table.h) into a shared object in the compile cache (cache.hpp), and
/// loading it with its checks.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/jit/cache.hpp"
#include "nhc/runtime/model.hpp"

namespace nhc::jit {

/// How a header becomes a shared object.
struct CompileOptions {
  /// The C++ compiler; empty: `$NHC_CXX`, else the one that built nhc.
  std::string compiler;
  /// Optimization and extra flags; the flags the contract needs (-std=c++17 -fPIC -shared,
  /// hidden visibility, stripped) are always added.
  std::vector<std::string> flags{"-O2"};
  /// Headers longer than this many bytes are compiled with -O0 in place of the -O flags above:
  /// on long straight-line code the optimizer costs 4–5 times the compile at -O0 and the whole
  /// run gains little or nothing, the integration being mostly the solver's own work
  /// (bench/compile-time.md, "Optimization level by measured benefit": the Whipple bicycle's
  /// 155 kB header 0.8 s instead of 3.6 s at -O1, its 5 s run 4 ms either way; the knife chain at
  /// N = 64 and 512). Shorter headers compile in well under a second at -O2, where the optimizer
  /// pays for runs that are long. 0: always the flags as given.
  std::size_t long_header_bytes = 100000;
  /// Translation units a generated header is compiled as, in parallel, and linked into one
  /// library, when its banner says it can be split (kTranslationUnitsBanner of
  /// nhc/emit/header_printer.hpp: generated headers from HeaderOptions::split_from_bytes); other
  /// headers are always one. 0: automatic, as many as `jobs`, at most the header's own limit.
  int translation_units = 0;
  /// Compiler processes run at once; 0: the number of processors.
  int jobs = 0;
  /// With GCC, caps on two optimizer searches that grow with the square of a straight-line
  /// function's length (alias queries per memory access in value numbering, memory locations
  /// cselib tracks), which dominate -O2 on generated code (bench/compile-time.md); false: GCC's
  /// defaults.
  bool bounded_optimizer = true;
  /// Extra include directories (-I), searched before the one that provides
  /// nhc/runtime/model_table.h (always added: hand-written headers include it).
  std::vector<std::filesystem::path> include_directories;
  /// Empty: default_cache_directory().
  std::filesystem::path cache_directory;
  /// Seconds the compiler may run before it is stopped (EnvironmentError); none:
  /// `$NHC_COMPILE_TIMEOUT`, else default_compile_timeout(); 0: no limit.
  std::optional<double> timeout_seconds;
  /// Receives one-line warnings (a cache entry rejected and rebuilt, an unsafe cache directory
  /// replaced); empty: printed on standard error as `nhc: warning: …`.
  Warning warn;
};

/// The optimization and extra flags a header of `header_bytes` is compiled with: options.flags,
/// with -O0 in place of their -O flags above options.long_header_bytes (the one place of the
/// policy; the compile cache's key holds the result).
std::vector<std::string> optimization_flags(const CompileOptions& options, std::size_t header_bytes);

/// The compiler's time limit when neither CompileOptions nor NHC_COMPILE_TIMEOUT sets one.
inline constexpr double default_compile_timeout() { return 600; }

/// `$NHC_CACHE_DIR`, else `$XDG_CACHE_HOME/nhc`, else `~/.cache/nhc`, else a directory of the
/// user's own under the temporary directory (default_cache_location()).
std::filesystem::path default_cache_directory();

/// A shared object built from a header, and whether the cache already held it.
struct CompiledLibrary {
  std::filesystem::path path;
  bool reused = false;
  double seconds = 0;         ///< compiling (or finding it in the cache)
  int translation_units = 1;  ///< it was compiled as (CompileOptions::translation_units)
  /// What the library records of itself (exported as `nhc_model_build_key`): the SHA-256 of
  /// nhc's version, the compiler, its version, the flags, the number of translation units and the
  /// header, and the scene and model.
  std::string build_record;
};

/// The scene and model a library must be built for; empty names are not checked (a hand-written
/// header compiled by file).
struct ModelIdentity {
  std::string scene;
  std::string model;
};

/// Compiles `header_text` (a complete model header defining one model table) into a shared
/// object exporting only `nhc_model_table_get` and `nhc_model_build_key`, or reuses the cached
/// one when its checks pass (cache.hpp; a failing entry is rebuilt with a warning). `label`
/// names the header in messages and the cache entry (a C++ identifier, e.g. the generated
/// namespace). Throws EnvironmentError when the compiler is missing, fails or times out (with
/// its first errors), or the cache cannot be written.
CompiledLibrary compile_header(const std::string& header_text, const std::string& label,
                               const CompileOptions& options = {}, const ModelIdentity& identity = {});

/// A header file on disk (e.g. a hand-written model), compiled as compile_header() does, with
/// its own directory on the include path.
CompiledLibrary compile_header_file(const std::filesystem::path& header, const CompileOptions& options = {});

/// compile_header(), then the library loaded and checked: its `nhc_model_build_key` is the
/// record it was built for and its table names `identity`'s scene and model. A cached entry
/// failing these checks is discarded and rebuilt once, with a warning. Throws EnvironmentError
/// when the library cannot be loaded.
std::pair<CompiledLibrary, runtime::Model> compile_and_load(const std::string& header_text, const std::string& label,
                                                            const ModelIdentity& identity,
                                                            const CompileOptions& options = {});

}  // namespace nhc::jit
