// nhc simulate SCENE [--model M] [--t-end T] [--rtol R] [--atol A] [--project] [-o FILE.csv]
//
// The whole pipeline on one model: derive, reduce to index 1, generate the header
// (docs/generated-code.md), compile it with the C++ compiler found at configure time into a
// cached shared object, load it, integrate with nhc::runtime (IDA), write the CSV and print a
// summary. Numerical failures (the Appell–Hamel stop at t*, singular iteration matrices, NaN)
// end with a diagnostic naming t and exit code 3; the CSV then holds the solution up to there.
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/errors.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

#ifndef NHC_CXX_COMPILER
#define NHC_CXX_COMPILER "c++"
#endif

namespace nhc::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct SimulateOptions {
  std::string scene_path;
  std::string model;
  std::optional<double> t_end, rtol, atol;
  bool project = false;
  int outputs = 200;
  std::string output;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// FNV-1a, 64 bit: a stable hash for the cache key (std::hash is not stable across builds).
std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 1469598103934665603ULL) {
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ULL;
  return h;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs a shell command; returns its exit status and fills `output` with stdout and stderr.
int run_command(const std::string& command, std::string& output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path cache_directory() {
  if (const char* dir = std::getenv("NHC_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "nhc";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "nhc";
  return fs::temp_directory_path() / ("nhc-cache-" + std::to_string(getuid()));
}

struct CompiledModel {
  std::string path;
  bool reused = false;
};

/// Compiles the generated header into a shared object exporting nhc_model_table_get, or reuses
/// the cached one: the key hashes the code, the compiler's path and version, and the flags.
CompiledModel compile_model(const GeneratedHeader& header) {
  const std::string compiler = NHC_CXX_COMPILER;
  const std::string flags = "-std=c++17 -O2 -fPIC -shared";
  std::string version;
  run_command(shell_quote(compiler) + " --version", version);
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

  const std::string suffix = ".tmp" + std::to_string(getpid());
  const fs::path src = dir / (stem + ".cpp" + suffix), out = dir / (stem + ".so" + suffix);
  {
    std::ofstream file(src);
    file << source;
    if (!file) throw std::runtime_error("cannot write " + src.string());
  }
  const std::string command = shell_quote(compiler) + " " + flags + " -x c++ -o " + shell_quote(out.string()) + " " +
                              shell_quote(src.string());
  std::string messages;
  const int status = run_command(command, messages);
  fs::remove(src, ec);
  if (status != 0 || !fs::exists(out)) {
    fs::remove(out, ec);
    throw std::runtime_error("the C++ compiler failed on the generated code of " + header.file_name + "\n  " + command +
                             "\n" + messages);
  }
  fs::rename(out, library, ec);  // atomic: concurrent runs produce the same bytes
  if (ec) throw std::runtime_error("cannot move " + out.string() + " to " + library.string() + ": " + ec.message());
  return {library.string(), false};
}

ModelKind chosen_model(const Scene& scene, const std::string& name) {
  if (!name.empty()) return *parse_model_kind(name);
  if (scene.simulate.model) return *scene.simulate.model;
  for (ModelKind m : scene.models)
    if (m == ModelKind::chetaev) return m;
  return scene.models.empty() ? ModelKind::chetaev : scene.models.front();
}

/// The scene's [initial] as the runtime's InitialState: `x = [x0, x'0]` gives the states x and x';
/// values beyond the states' orders are y' guesses.
runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model) {
  runtime::InitialState s;
  s.t0 = scene.initial.t0;
  const int n = model.n_states();
  s.y.assign(n, 0.0);
  s.yp.assign(n, 0.0);
  s.given.assign(n, false);
  for (int i = 0; i < n; ++i) {
    const std::string name = model.variable_name(model.table().state_variable[i]);
    const int order = model.table().state_order[i];
    const auto it = scene.initial.values.find(name);
    if (it == scene.initial.values.end()) continue;
    if (static_cast<int>(it->second.size()) > order) {
      s.y[i] = it->second[order];
      s.given[i] = model.is_differential(i);  // algebraic values are only guesses
    }
    if (static_cast<int>(it->second.size()) > order + 1) s.yp[i] = it->second[order + 1];
  }
  return s;
}

std::string format(double v, int precision = 3) {
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

}  // namespace

CommandRunner add_simulate_command(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand(
      "simulate", "derive, generate, compile and integrate one model of a scene with SUNDIALS IDA");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember({"vakonomic", "chetaev", "holder", "suslov"}));
  sub->add_option("--t-end", options->t_end, "final time (default: [simulate] t_end)");
  sub->add_option("--rtol", options->rtol, "relative tolerance (default: [simulate] rtol)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--atol", options->atol, "absolute tolerance (default: [simulate] atol)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--project", options->project, "project onto the hidden constraints (docs/projection.md)");
  sub->add_option("--outputs", options->outputs, "number of output intervals (default 200)")
      ->check(CLI::PositiveNumber);
  sub->add_option("-o,--output", options->output, "CSV file for the solution");

  return [options]() {
    // Derive, reduce, generate.
    const auto derive_start = Clock::now();
    const Scene scene = load_scene(options->scene_path);
    const ModelKind kind = chosen_model(scene, options->model);
    const DerivedModel derived = derive_model(scene, kind);
    if (!derived.applicable)
      throw MathError("the " + to_string(kind) + " model does not apply to " + scene.name + ": " + derived.reason);
    const Index1System system = reduce_to_index1(scene, derived);
    HeaderOptions header_options;
    header_options.jacobian = system.size() >= 40 ? JacobianKind::sparse : JacobianKind::dense;
    const GeneratedHeader header = generate_header(scene, system, header_options);
    const double derive_seconds = seconds_since(derive_start);

    // Compile (or reuse) and load.
    const auto compile_start = Clock::now();
    const CompiledModel compiled = compile_model(header);
    const runtime::Model model = runtime::Model::load(compiled.path);
    const double compile_seconds = seconds_since(compile_start);

    // Integrate.
    runtime::IntegratorOptions io;
    io.rtol = options->rtol.value_or(scene.simulate.rtol);
    io.atol = options->atol.value_or(scene.simulate.atol);
    io.projection = options->project ? runtime::ProjectionMethod::in_place : runtime::ProjectionMethod::none;
    const double t0 = scene.initial.t0, t_end = options->t_end.value_or(scene.simulate.t_end);
    if (!(t_end > t0))
      throw InputError({options->scene_path, 0, 0}, "--t-end " + format(t_end, 17) + " must be after t0 = " + format(t0, 17));
    const std::vector<double> p = model.default_parameters();
    const runtime::RunResult run =
        runtime::simulate(model, p, initial_state_of(scene, model), runtime::output_times(t0, t_end, options->outputs), io);
    if (!options->output.empty()) runtime::write_csv(options->output, model, p, run.samples);

    // Summary.
    const runtime::Statistics& st = run.statistics;
    const runtime::DriftReport drift = runtime::measure_drift(model, p, run.samples);
    std::cout << "nhc simulate: " << scene.name << ", model " << to_string(kind) << ", t from " << t0 << " to "
              << (run.samples.empty() ? t0 : run.samples.back().t) << " (of " << t_end << "), rtol " << io.rtol
              << ", atol " << io.atol << (options->project ? ", projection" : "") << "\n"
              << "  steps " << st.steps << ", residual evaluations " << st.residual_evaluations
              << ", Jacobian evaluations " << st.jacobian_evaluations << " (" << st.linear_solver << ", "
              << st.jacobian << "), error-test failures " << st.error_test_failures << ", nonlinear failures "
              << st.nonlinear_failures;
    if (options->project) std::cout << ", projections " << st.projections;
    std::cout << "\n  time: derive " << format(derive_seconds) << " s, compile " << format(compile_seconds) << " s"
              << (compiled.reused ? " (cached)" : "") << ", integrate "
              << format(st.initialization_seconds + st.integration_seconds) << " s\n";
    if (model.n_reference() > 0) std::cout << "  max reference error " << format(drift.max_error) << "\n";
    if (model.n_hidden() > 0) std::cout << "  max hidden-constraint drift " << format(drift.max_hidden) << "\n";
    for (int k = 0; k < model.n_invariants(); ++k)
      std::cout << "  invariant " << model.table().invariant_names[k] << ": max drift "
                << format(drift.invariant_drift[k]) << " (relative " << format(drift.invariant_relative[k]) << ")\n";
    if (!options->output.empty()) std::cout << "  wrote " << options->output << " (" << run.samples.size() << " rows)\n";
    if (run.failure) {
      std::cout.flush();
      std::cerr << "nhc: error: " << run.failure->what() << "\n";
      return kExitMathFailure;
    }
    return kExitOk;
  };
}

}  // namespace nhc::cli
