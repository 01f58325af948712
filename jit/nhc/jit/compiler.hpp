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
  /// GCC's optimizer on megabytes of straight-line code is slower than any integration it would
  /// speed up (the Whipple bicycle's 4.5 MB header: -O0 29 s and 2.3 GB; -O1 still running
  /// after 8 min; with its common arguments shared it is 2.0 MB, and -O1 took over 4 minutes and
  /// 8 GB before it was stopped). The knife-edge chain at N = 512 (1.3 MB before the sharing, one
  /// residual function of about 1 MB) still compiles at -O1 in about 20 s and its long runs want
  /// the optimized code, hence the threshold above it. 0: always the flags as given.
  std::size_t large_header_bytes = 1500000;
  /// Headers longer than this many bytes (and at most large_header_bytes) are compiled with -O1
  /// in place of -O2 or -O3 among the flags: on long straight-line code -O2's further passes
  /// lengthen the compile and do not shorten the run (bench/compile-time.md, the knife-edge
  /// chain from N = 64). 0: the flags as given.
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

/// The compiler's time limit when neither CompileOptions nor NHC_COMPILE_TIMEOUT sets one.
inline constexpr double default_compile_timeout() { return 600; }

/// `$NHC_CACHE_DIR`, else `$XDG_CACHE_HOME/nhc`, else `~/.cache/nhc`, else a directory of the
/// user's own under the temporary directory (default_cache_location()).
std::filesystem::path default_cache_directory();

/// A shared object built from a header, and whether the cache already held it.
struct CompiledLibrary {
  std::filesystem::path path;
  bool reused = false;
  double seconds = 0;  ///< compiling (or finding it in the cache)
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
