// Compiling model headers into cached shared objects (compiler.hpp).
#include "nhc/jit/compiler.hpp"

#include <unistd.h>

#include <chrono>
#include <cctype>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "nhc/emit/model_table_text.hpp"
#include "nhc/io/shell.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/jit/subprocess.hpp"

#ifndef NHC_CXX_COMPILER
#define NHC_CXX_COMPILER "c++"
#endif

namespace nhc::jit {

namespace fs = std::filesystem;

namespace {

/// FNV-1a, 64 bit: a stable hash for the cache key (std::hash is not stable across builds).
std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 1469598103934665603ULL) {
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  return h;
}

/// The translation unit that wraps a model header: the table's entry point is the only symbol
/// the shared object exports (every other symbol is hidden), so two models whose headers use the
/// same namespace can never resolve to each other's table.
std::string translation_unit(const std::string& header_name) {
  return "// nhc::jit: exports the model table of " + header_name +
         "\n"
         "#define NHC_EXPORT_MODEL_TABLE\n"
         "struct nhc_model_table;\n"
         "extern \"C\" __attribute__((visibility(\"default\"))) const nhc_model_table* nhc_model_table_get(void);\n"
         "#include \"" +
         header_name + "\"\n";
}

/// The flags every model library is built with, after the user's optimization flags.
std::vector<std::string> contract_flags(const std::string& compiler_version) {
  std::vector<std::string> flags{"-std=c++17", "-fPIC", "-shared", "-fvisibility=hidden",
                                 "-fvisibility-inlines-hidden"};
  // GCC gives function-local statics of inline functions STB_GNU_UNIQUE binding, which the
  // dynamic linker shares across every loaded library; hidden visibility already avoids it, and
  // -fno-gnu-unique makes sure.
  if (compiler_version.find("clang") == std::string::npos) flags.emplace_back("-fno-gnu-unique");
  return flags;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  file.flush();
  if (!file) throw std::runtime_error("cannot write " + path.string());
}

/// `dir`/include/nhc/runtime/model_table.h (the embedded text of the one definition), for
/// hand-written headers that include it; returns `dir`/include. Written through a temporary
/// name and renamed: concurrent runs write the same bytes.
fs::path table_include_directory(const fs::path& dir) {
  const fs::path include = dir / "include";
  const fs::path header = include / "nhc" / "runtime" / "model_table.h";
  std::ifstream existing(header);
  std::ostringstream present;
  present << existing.rdbuf();
  if (existing && present.str() == model_table_text()) return include;
  std::error_code ec;
  fs::create_directories(header.parent_path(), ec);
  if (ec) throw std::runtime_error("cannot create " + header.parent_path().string() + ": " + ec.message());
  const TemporaryFile temporary(unique_temporary_name(header.string()));
  write_text(temporary.path(), model_table_text());
  fs::rename(temporary.path(), header, ec);
  if (ec) throw std::runtime_error("cannot write " + header.string() + ": " + ec.message());
  return include;
}

}  // namespace

fs::path default_cache_directory() {
  if (const char* dir = std::getenv("NHC_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "nhc";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "nhc";
  return fs::temp_directory_path() / ("nhc-cache-" + std::to_string(getuid()));
}

CompiledLibrary compile_header(const std::string& header_text, const std::string& label,
                               const CompileOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::string compiler = options.compiler.empty() ? NHC_CXX_COMPILER : options.compiler;
  std::string version;
  run_process({compiler, "--version"}, version);
  const fs::path dir = options.cache_directory.empty() ? default_cache_directory() : options.cache_directory;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the cache directory " + dir.string() + ": " + ec.message());
  std::vector<std::string> flags = options.flags;
  for (std::string& f : contract_flags(version)) flags.push_back(std::move(f));
  for (const fs::path& include : options.include_directories) flags.push_back("-I" + include.string());
  flags.push_back("-I" + table_include_directory(dir).string());
  std::string flag_text;
  for (const std::string& f : flags) flag_text += f + " ";
  char key[17];
  std::snprintf(key, sizeof key, "%016" PRIx64,
                fnv1a(std::string(NHC_VERSION) + "\n" + model_table_text() + "\n" + compiler + "\n" + version + "\n" + flag_text + "\n" +
                      header_text));

  const std::string stem = label + "-" + key;
  const fs::path library = dir / (stem + ".so");
  if (fs::exists(library)) return {library, true, elapsed()};

  // Names unique to this process and call, registered before they exist: concurrent runs never
  // share a temporary file, and an interrupt removes them (nhc/io/temporary_files.hpp).
  const TemporaryFile header_file(unique_temporary_name((dir / (stem + ".hpp")).string()));
  const TemporaryFile source_file(unique_temporary_name((dir / (stem + ".cpp")).string()));
  const TemporaryFile out_file(unique_temporary_name(library.string()));
  const fs::path out = out_file.path();
  write_text(header_file.path(), header_text);
  write_text(source_file.path(), translation_unit(fs::path(header_file.path()).filename().string()));
  std::vector<std::string> command{compiler};
  command.insert(command.end(), flags.begin(), flags.end());
  command.emplace_back("-o");
  command.push_back(out.string());
  for (const char* argument : {"-x", "c++"}) command.emplace_back(argument);
  command.push_back(source_file.path());
  std::string messages;
  const int status = run_process(command, messages);
  header_file.remove();
  source_file.remove();
  if (status != 0 || !fs::exists(out)) {
    out_file.remove();
    std::string command_line;
    for (const std::string& word : command) command_line += (command_line.empty() ? "" : " ") + shell_quote(word);
    throw std::runtime_error("the C++ compiler failed on the code of " + label + "\n  " + command_line + "\n" +
                             messages);
  }
  fs::rename(out, library, ec);  // atomic: concurrent runs produce the same bytes
  if (ec) out_file.remove();
  if (ec) throw std::runtime_error("cannot move " + out.string() + " to " + library.string() + ": " + ec.message());
  return {library, false, elapsed()};
}

CompiledLibrary compile_header_file(const fs::path& header, const CompileOptions& options) {
  std::ifstream in(header);
  if (!in) throw std::runtime_error("cannot read " + header.string());
  std::ostringstream text;
  text << in.rdbuf();
  std::string label = header.stem().string();
  for (char& c : label)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) c = '_';
  // Its own directory first: a hand-written header may include files next to it.
  CompileOptions with_directory = options;
  with_directory.include_directories.insert(with_directory.include_directories.begin(),
                                            fs::absolute(header).parent_path());
  return compile_header(text.str(), label, with_directory);
}

}  // namespace nhc::jit
