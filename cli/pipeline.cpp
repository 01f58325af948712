// The shared pipeline of the integrating commands (pipeline.hpp).
#include "pipeline.hpp"

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/temporary_files.hpp"
#include "subprocess.hpp"

#ifndef NHC_CXX_COMPILER
#define NHC_CXX_COMPILER "c++"
#endif

namespace nhc::cli {

namespace fs = std::filesystem;

namespace {

/// FNV-1a, 64 bit: a stable hash for the cache key (std::hash is not stable across builds).
std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 1469598103934665603ULL) {
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  return h;
}

}  // namespace

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

fs::path cache_directory() {
  if (const char* dir = std::getenv("NHC_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "nhc";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "nhc";
  return fs::temp_directory_path() / ("nhc-cache-" + std::to_string(getuid()));
}

CompiledModel compile_model(const GeneratedHeader& header) {
  const std::string compiler = NHC_CXX_COMPILER;
  std::string version;
  run_process({compiler, "--version"}, version);
  // GCC gives the static table inside the inline model_table() STB_GNU_UNIQUE binding, which the
  // dynamic linker shares across every loaded library: the second of two models of one scene
  // (dense and sparse Jacobian, as nhc report loads them) would return the first one's table.
  std::string flags = "-std=c++17 -O2 -fPIC -shared";
  if (version.find("clang") == std::string::npos) flags += " -fno-gnu-unique";
  const std::string source = "#define NHC_EXPORT_MODEL_TABLE\n" + header.text;
  char key[17];
  std::snprintf(key, sizeof key, "%016" PRIx64, fnv1a(compiler + "\n" + version + "\n" + flags + "\n" + source));

  const fs::path dir = cache_directory();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the cache directory " + dir.string() + ": " + ec.message());
  const std::string stem = header.namespace_name + "-" + key;
  const fs::path library = dir / (stem + ".so");
  if (fs::exists(library)) return {library.string(), true};

  // Names unique to this process and call, registered before they exist: concurrent runs never
  // share a temporary file, and an interrupt removes them (nhc/io/temporary_files.hpp).
  const TemporaryFile src_file(unique_temporary_name((dir / (stem + ".cpp")).string()));
  const TemporaryFile out_file(unique_temporary_name(library.string()));
  const fs::path src = src_file.path(), out = out_file.path();
  {
    std::ofstream file(src);
    file << source;
    file.flush();
    if (!file) {
      src_file.remove();
      throw std::runtime_error("cannot write " + src.string());
    }
  }
  std::vector<std::string> command{compiler};
  for (std::istringstream words(flags); words;) {
    std::string word;
    if (words >> word) command.push_back(word);
  }
  for (const char* argument : {"-x", "c++", "-o"}) command.emplace_back(argument);
  command.push_back(out.string());
  command.push_back(src.string());
  std::string messages;
  const int status = run_process(command, messages);
  src_file.remove();
  if (status != 0 || !fs::exists(out)) {
    out_file.remove();
    std::string command_line;
    for (const std::string& word : command) command_line += (command_line.empty() ? "" : " ") + shell_quote(word);
    throw std::runtime_error("the C++ compiler failed on the generated code of " + header.file_name + "\n  " +
                             command_line + "\n" + messages);
  }
  fs::rename(out, library, ec);  // atomic: concurrent runs produce the same bytes
  if (ec) out_file.remove();
  if (ec) throw std::runtime_error("cannot move " + out.string() + " to " + library.string() + ": " + ec.message());
  return {library.string(), false};
}

BuiltModel build_model(const Scene& scene, ModelKind kind, std::optional<JacobianKind> jacobian_choice) {
  const auto derive_start = Clock::now();
  const DerivedModel derived = derive_model(scene, kind);
  if (!derived.applicable)
    throw MathError("the " + to_string(kind) + " model does not apply to " + scene.name + ": " + derived.reason);
  const Index1System system = reduce_to_index1(scene, derived);
  const JacobianKind jacobian =
      jacobian_choice.value_or(default_jacobian_kind(system.size()));
  HeaderOptions header_options;
  header_options.jacobian = jacobian;
  GeneratedHeader header = generate_header(scene, system, header_options);
  const double derive_seconds = seconds_since(derive_start);

  const auto compile_start = Clock::now();
  CompiledModel compiled = compile_model(header);
  runtime::Model model = runtime::Model::load(compiled.path);
  return BuiltModel{kind,           jacobian,       std::move(header), std::move(compiled), std::move(model),
                    derive_seconds, seconds_since(compile_start)};
}

runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model) {
  return runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
}

std::string format_number(double v, int precision) {
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

}  // namespace nhc::cli
