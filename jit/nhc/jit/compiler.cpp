// Compiling model headers into cached shared objects (compiler.hpp).
#include "nhc/jit/compiler.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <fstream>
#include <functional>
#include <optional>
#include <iostream>
#include <sstream>
#include <thread>

#include "nhc/errors.hpp"
#include "nhc/emit/header_printer.hpp"
#include "nhc/emit/model_table_text.hpp"
#include "nhc/io/shell.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/jit/cache_size.hpp"
#include "nhc/tools/sha256.hpp"
#include "nhc/tools/subprocess.hpp"
#include "nhc/long_work.hpp"

#ifndef NHC_CXX_COMPILER
#define NHC_CXX_COMPILER "c++"
#endif

namespace nhc::jit {

namespace fs = std::filesystem;
using tools::ProcessResult;
using tools::run_process;
using tools::sha256_file_hex;
using tools::sha256_hex;

namespace {

/// `text` as the body of a C string literal: printable ASCII kept, the rest as octal escapes.
std::string c_string_body(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\' && c != '?') {
      out += static_cast<char>(c);
    } else {
      char escape[5];
      std::snprintf(escape, sizeof escape, "\\%03o", c);
      out += escape;
    }
  }
  return out;
}

/// The translation unit that wraps a model header: the table's entry point and the build record
/// are the only symbols the shared object exports (every other symbol is hidden), so two models
/// whose headers use the same namespace can never resolve to each other's table. The header is
/// included, not compiled as the main file: no "#pragma once in main file" warning. With
/// `parts` > 1 it is part `part` of a header compiled as that many translation units (the
/// header's NHC_PART protocol); the record lives in part 0, with the table.
std::string translation_unit(const std::string& header_name, const std::string& build_record, int part = 0,
                             int parts = 1) {
  std::string text = "// nhc::jit: exports the model table of " + header_name +
                     " and the record of what it was built from\n"
                     "#define NHC_EXPORT_MODEL_TABLE\n";
  if (parts > 1)
    text += "#define NHC_PARTS " + std::to_string(parts) + "\n#define NHC_PART " + std::to_string(part) + "\n";
  text +=
      "struct nhc_model_table;\n"
      "extern \"C\" __attribute__((visibility(\"default\"))) const nhc_model_table* nhc_model_table_get(void);\n";
  if (part == 0)
    text += "extern \"C\" __attribute__((visibility(\"default\"))) const char nhc_model_build_key[] = \"" +
            c_string_body(build_record) + "\";\n";
  return text + "#include \"" + header_name + "\"\n";
}

/// The most translation units `header_text` may be compiled as: the number its banner states
/// (kTranslationUnitsBanner), else 1.
int splittable_parts(const std::string& header_text) {
  const std::size_t at = header_text.find(kTranslationUnitsBanner);
  if (at == std::string::npos) return 1;
  const int parts = std::atoi(header_text.c_str() + at + std::strlen(kTranslationUnitsBanner));
  return std::clamp(parts, 1, kMaxTranslationUnits);
}

int compile_jobs(const CompileOptions& options) {
  if (options.jobs > 0) return options.jobs;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// How many translation units `header_text` is compiled as (CompileOptions::translation_units).
int chosen_parts(const CompileOptions& options, const std::string& header_text) {
  const int most = splittable_parts(header_text);
  if (options.translation_units > 0) return std::min(options.translation_units, most);
  return std::min(compile_jobs(options), most);
}

/// GCC's caps on its quadratic searches over long straight-line functions (bounded_optimizer):
/// they change nothing in short functions, where the searches end before the caps.
std::vector<std::string> optimizer_bounds(const CompileOptions& options, const std::string& compiler_version,
                                          const std::vector<std::string>& optimization) {
  if (!options.bounded_optimizer || compiler_version.find("clang") != std::string::npos) return {};
  if (std::find(optimization.begin(), optimization.end(), "-O0") != optimization.end()) return {};
  return {"--param=sccvn-max-alias-queries-per-access=50", "--param=max-cselib-memory-locations=50"};
}

/// Runs `commands` (each writing its own file), at most `jobs` at a time; the first failure is
/// rethrown once all have ended.
void run_all(const std::vector<std::function<void()>>& commands, int jobs) {
  std::vector<std::exception_ptr> errors(commands.size());
  std::atomic<std::size_t> next{0};
  LongWorkObserver* const observer = current_observer();  // every thread's compiler may be stopped
  const WaitingForProcess waiting;
  auto worker = [&] {
    std::optional<ObservedWork> observed;
    if (observer != nullptr) observed.emplace(*observer);
    for (std::size_t k; (k = next++) < commands.size();) try {
        commands[k]();
      } catch (...) {
        errors[k] = std::current_exception();
      }
  };
  std::vector<std::thread> threads;
  const std::size_t n = std::min(commands.size(), static_cast<std::size_t>(std::max(1, jobs)));
  for (std::size_t t = 1; t < n; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();
  for (const std::exception_ptr& e : errors) try {  // a stop request first: it ended the others' compilers
      if (e) std::rethrow_exception(e);
    } catch (const WorkInterrupted&) {
      throw;
    } catch (...) {
    }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

/// The flags every model library is built with, after the user's optimization flags.
std::vector<std::string> contract_flags(const std::string& compiler_version) {
  // -s: no symbol table, so that the bytes do not depend on the temporary source file's name
  // and concurrent builds of one entry write identical files (and digests).
  std::vector<std::string> flags{"-std=c++17", "-fPIC", "-shared", "-fvisibility=hidden", "-fvisibility-inlines-hidden",
                                 "-s"};
  // GCC gives function-local statics of inline functions STB_GNU_UNIQUE binding, which the
  // dynamic linker shares across every loaded library; hidden visibility already avoids it, and
  // -fno-gnu-unique makes sure.
  if (compiler_version.find("clang") == std::string::npos) flags.emplace_back("-fno-gnu-unique");
  return flags;
}

std::string chosen_compiler(const CompileOptions& options) {
  if (!options.compiler.empty()) return options.compiler;
  if (const char* cxx = std::getenv("NHC_CXX"); cxx && *cxx) return cxx;
  return NHC_CXX_COMPILER;
}

double compile_timeout(const CompileOptions& options) {
  if (options.timeout_seconds) return *options.timeout_seconds;
  const char* text = std::getenv("NHC_COMPILE_TIMEOUT");
  if (!text || !*text) return default_compile_timeout();
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (*end != '\0' || !(seconds >= 0) || seconds > 1e9)
    throw InputError({"NHC_COMPILE_TIMEOUT", 0, 0},
                     std::string("'") + text + "' is not a number of seconds (0: no limit)");
  return seconds;
}

Warning warning_sink(const CompileOptions& options) {
  if (options.warn) return options.warn;
  return [](const std::string& line) { std::cerr << "nhc: warning: " << line << std::endl; };
}

/// The compiler's output from its first error (or failure, as the linker says) on, at most
/// `max_lines` lines.
std::string first_errors(const std::string& output, std::size_t max_lines = 20) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::size_t first = 0;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (lines[i].find("error") != std::string::npos || lines[i].find("failed") != std::string::npos) {
      first = i;
      break;
    }
  std::string text;
  const std::size_t last = std::min(lines.size(), first + max_lines);
  for (std::size_t i = first; i < last; ++i) text += "  " + lines[i] + "\n";
  if (last < lines.size()) text += "  [" + std::to_string(lines.size() - last) + " more lines]\n";
  if (!text.empty()) text.pop_back();  // the caller's message ends the last line
  return text;
}

/// A system reason the compiler's output states (a full disk, a file-size limit), if any.
std::string system_reason_in(const std::string& output) {
  for (int error : {ENOSPC, EFBIG, EDQUOT, EACCES, EROFS}) {
    const std::string reason = std::strerror(error);
    if (output.find(reason) != std::string::npos) return reason;
  }
  return {};
}

void write_text(const fs::path& path, const std::string& text) {
  errno = 0;
  std::ofstream file(path);
  file << text;
  file.close();
  if (!file)
    throw EnvironmentError("cannot write " + path.string() + ": " + (errno ? std::strerror(errno) : "write failed"));
}

/// The compiler's version line(s); EnvironmentError when it cannot be run.
std::string compiler_version(const std::string& compiler, double timeout) {
  std::string version;
  const ProcessResult r = run_process({compiler, "--version"}, version, timeout);
  if (!r.started)
    throw EnvironmentError("the C++ compiler " + compiler + " cannot be run: " + r.start_error +
                           " (set NHC_CXX to a C++17 compiler)");
  if (r.timed_out)
    throw EnvironmentError("the C++ compiler " + compiler + " did not answer --version within " +
                           std::to_string(static_cast<long long>(timeout)) + " s (NHC_COMPILE_TIMEOUT)");
  if (!r.ok())
    throw EnvironmentError("the C++ compiler " + compiler + " does not work (" + compiler + " --version failed):\n" +
                           first_errors(version));
  return version;
}

/// The compiler run into `out`; EnvironmentError with its first errors when it fails.
void run_compiler(const std::vector<std::string>& command, const std::string& label, const fs::path& out,
                  const fs::path& cache, double timeout) {
  std::string messages;
  const ProcessResult r = run_process(command, messages, timeout);
  if (r.ok() && fs::exists(out)) return;
  std::string command_line;
  for (const std::string& word : command) command_line += (command_line.empty() ? "" : " ") + shell_quote(word);
  if (!r.started)
    throw EnvironmentError("the C++ compiler " + command.front() + " cannot be run: " + r.start_error +
                           " (set NHC_CXX to a C++17 compiler)");
  if (r.timed_out)
    throw EnvironmentError("the C++ compiler took longer than " + std::to_string(static_cast<long long>(timeout)) +
                           " s on the code of " + label +
                           " and was stopped (raise NHC_COMPILE_TIMEOUT, 0: no limit)\n  " + command_line);
  // Memory is the machine's, not the code's: cc1plus says "out of memory allocating …" under a
  // ulimit, "virtual memory exhausted" when the system runs out; the kernel's OOM killer sends 9.
  const bool out_of_memory = messages.find("out of memory") != std::string::npos ||
                             messages.find("virtual memory exhausted") != std::string::npos ||
                             messages.find("Cannot allocate memory") != std::string::npos || r.signal == 9;
  if (out_of_memory)
    throw EnvironmentError("the C++ compiler ran out of memory compiling the code of " + label +
                           (r.signal == 9 ? " (killed by signal 9, as the kernel does when memory runs out)" : "") +
                           ": free memory or raise the limit (ulimit -v)\n  " + command_line + "\n" +
                           first_errors(messages));
  const std::string reason = system_reason_in(messages);
  if (!reason.empty())
    throw EnvironmentError("cannot compile " + label + " into the cache " + cache.string() + ": " + reason + "\n" +
                           first_errors(messages));
  throw EnvironmentError("the C++ compiler failed on the code of " + label +
                         (r.signal ? " (killed by signal " + std::to_string(r.signal) + ")" : "") +
                         " (if it compiles other C++17 code, this is a bug in nhc: please report it)\n  " +
                         command_line + "\n" + first_errors(messages));
}

/// Renames `from` to `to`; EnvironmentError naming both when it fails.
void move_into_place(const fs::path& from, const fs::path& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0)
    throw EnvironmentError("cannot move " + from.string() + " to " + to.string() + ": " + std::strerror(errno));
}

/// The library loaded and checked against what it was built for; nullopt with `problem` set
/// when it fails a check.
std::optional<runtime::Model> load_checked(const CompiledLibrary& library, const ModelIdentity& identity,
                                           std::string& problem) {
  // Opened once here, without calling into it, to read the record; Model::load opens the same
  // handle again (reference counted) and only then runs the table's entry point.
  dlerror();
  void* handle = dlopen(library.path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    problem = std::string("dlopen failed: ") + (why ? why : "unknown reason");
    return std::nullopt;
  }
  const char* record = static_cast<const char*>(dlsym(handle, "nhc_model_build_key"));
  if (!record || library.build_record != record) {
    dlclose(handle);
    problem = record ? "built for something else (its nhc_model_build_key differs)" : "no nhc_model_build_key";
    return std::nullopt;
  }
  std::optional<runtime::Model> model;
  try {
    model = runtime::Model::load(library.path.string());
  } catch (const std::exception& e) {
    dlclose(handle);
    problem = std::string("no valid model table: ") + e.what();
    return std::nullopt;
  }
  dlclose(handle);
  if ((!identity.scene.empty() && model->scene_name() != identity.scene) ||
      (!identity.model.empty() && model->model_name() != identity.model)) {
    problem = "it holds the model " + model->model_name() + " of scene " + model->scene_name() + ", not " +
              identity.model + " of " + identity.scene;
    return std::nullopt;
  }
  return model;
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
  if (ec) throw EnvironmentError("cannot create " + header.parent_path().string() + ": " + ec.message());
  const TemporaryFile temporary(unique_temporary_name(header.string()));
  write_text(temporary.path(), model_table_text());
  fs::rename(temporary.path(), header, ec);
  if (ec) throw EnvironmentError("cannot write " + header.string() + ": " + ec.message());
  return include;
}

}  // namespace

std::vector<std::string> optimization_flags(const CompileOptions& options, std::size_t header_bytes) {
  if (options.long_header_bytes == 0 || header_bytes <= options.long_header_bytes) return options.flags;
  std::vector<std::string> flags{"-O0"};
  for (const std::string& f : options.flags)
    if (f.rfind("-O", 0) != 0) flags.push_back(f);
  return flags;
}

fs::path default_cache_directory() { return default_cache_location().path; }

CompiledLibrary compile_header(const std::string& header_text, const std::string& label, const CompileOptions& options,
                               const ModelIdentity& identity) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const Warning warn = warning_sink(options);
  const std::string compiler = chosen_compiler(options);
  const double timeout = compile_timeout(options);
  const std::string version = compiler_version(compiler, timeout);
  std::vector<std::string> flags = optimization_flags(options, header_text.size());
  for (std::string& f : optimizer_bounds(options, version, flags)) flags.push_back(std::move(f));
  for (std::string& f : contract_flags(version)) flags.push_back(std::move(f));
  for (const fs::path& include : options.include_directories) flags.push_back("-I" + include.string());
  std::string flag_text;
  for (const std::string& f : flags) flag_text += f + " ";
  const int parts = chosen_parts(options, header_text);
  const std::string key =
      sha256_hex(std::string(NHC_VERSION) + "\n" + model_table_text() + "\n" + compiler + "\n" + version + "\n" +
                 flag_text + "\n" + "translation units " + std::to_string(parts) + "\n" + header_text);
  const std::string record = "nhc build key " + key + "\nscene " + identity.scene + "\nmodel " + identity.model + "\n";

  const fs::path dir = options.cache_directory.empty()
                           ? private_cache_directory(default_cache_location(), warn)
                           : private_cache_directory({options.cache_directory, false}, warn);
  // Hand-written headers include nhc/runtime/model_table.h: the embedded one definition.
  flags.push_back("-I" + table_include_directory(dir).string());
  const std::string stem = label + "-" + key.substr(0, 16);
  const fs::path library = dir / (stem + ".so");
  std::error_code ec;
  if (fs::exists(fs::symlink_status(library, ec))) {
    const std::string problem = entry_problem(library);
    if (problem.empty()) {
      mark_used(library);
      return {library, true, elapsed(), parts, record};
    }
    warn("cache entry " + library.string() + " rejected: " + problem + "; rebuilding it");
    discard_entry(library);
  }

  // Names unique to this process and call, registered before they exist: concurrent runs never
  // share a temporary file, and an interrupt removes them (nhc/io/temporary_files.hpp).
  const TemporaryFile header_file(unique_temporary_name((dir / (stem + ".hpp")).string()));
  const TemporaryFile out_file(unique_temporary_name(library.string()));
  const TemporaryFile digest_file(unique_temporary_name(digest_path(library).string()));
  // One source (and, when split, one object) per part, all named before any is written.
  std::deque<TemporaryFile> sources, objects;  // not movable: a deque keeps them in place
  for (int k = 0; k < parts; ++k) {
    sources.emplace_back(unique_temporary_name((dir / (stem + ".cpp")).string()));
    if (parts > 1) objects.emplace_back(unique_temporary_name((dir / (stem + ".o")).string()));
  }
  const fs::path out = out_file.path();
  write_text(header_file.path(), header_text);
  const std::string header_name = fs::path(header_file.path()).filename().string();
  auto compile_command = [&](const std::string& source, const std::string& output, bool object) {
    std::vector<std::string> command{compiler};
    command.insert(command.end(), flags.begin(), flags.end());
    if (object) command.emplace_back("-c");
    command.emplace_back("-o");
    command.push_back(output);
    for (const char* argument : {"-x", "c++"}) command.emplace_back(argument);
    command.push_back(source);
    return command;
  };
  std::vector<std::function<void()>> compiles;
  for (int k = 0; k < parts; ++k) {
    const fs::path source = sources[static_cast<size_t>(k)].path();
    write_text(source, translation_unit(header_name, record, k, parts));
    const fs::path object = parts > 1 ? fs::path(objects[static_cast<size_t>(k)].path()) : out;
    compiles.emplace_back([&, source, object] {
      run_compiler(compile_command(source.string(), object.string(), parts > 1), label, object, dir, timeout);
    });
  }
  run_all(compiles, compile_jobs(options));
  if (parts > 1) {
    std::vector<std::string> link{compiler};
    link.insert(link.end(), flags.begin(), flags.end());
    link.emplace_back("-o");
    link.push_back(out.string());
    for (const TemporaryFile& object : objects) link.push_back(object.path());
    run_compiler(link, label, out, dir, timeout);
  }
  header_file.remove();
  for (const TemporaryFile& file : sources) file.remove();
  for (const TemporaryFile& file : objects) file.remove();
  const std::optional<std::string> digest = sha256_file_hex(out);
  if (!digest) throw EnvironmentError("cannot read " + out.string() + ": " + std::strerror(errno));
  write_text(digest_file.path(), digest_text(*digest, library.filename().string()));
  // The digest first: a reader that finds the library finds its digest. Concurrent runs write
  // the same bytes (-s), so either run's pair matches.
  move_into_place(digest_file.path(), digest_path(library));
  move_into_place(out, library);
  evict_over_limit(dir, library);
  return {library, false, elapsed(), parts, record};
}

CompiledLibrary compile_header_file(const fs::path& header, const CompileOptions& options) {
  std::ifstream in(header);
  if (!in) throw EnvironmentError("cannot read " + header.string() + ": " + std::strerror(errno));
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

std::pair<CompiledLibrary, runtime::Model> compile_and_load(const std::string& header_text, const std::string& label,
                                                            const ModelIdentity& identity,
                                                            const CompileOptions& options) {
  CompiledLibrary library = compile_header(header_text, label, options, identity);
  std::string problem;
  std::optional<runtime::Model> model = load_checked(library, identity, problem);
  if (!model && library.reused) {
    warning_sink(options)("cache entry " + library.path.string() + " rejected: " + problem + "; rebuilding it");
    discard_entry(library.path);
    library = compile_header(header_text, label, options, identity);
    model = load_checked(library, identity, problem);
  }
  if (!model) throw EnvironmentError("cannot load " + library.path.string() + ": " + problem);
  return {std::move(library), std::move(*model)};
}

}  // namespace nhc::jit
