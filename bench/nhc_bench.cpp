// nhc_bench: one benchmark measurement of nhc on one scene, printed as one JSON object.
//
//   nhc_bench SCENE --out DIR [--model M] [--jacobian auto|dense|sparse] [--t-end T]
//             [--rtol R] [--atol A] [--handwritten HEADER [--define NAME=VALUE]...] [--quick]
//             [--opt "FLAGS"] [--translation-units K] [--unbounded-optimizer]
//
// 1. derive + analyse (Pryce, index-1 reduction) + generate the header, timed per stage (best of
//    several runs when one is short); operation counts before/after CSE, per function;
// 2. compile the header into a shared object with nhc::jit, as `nhc simulate` does (a fresh
//    cache under --out, so that the compile is timed, not a cache hit);
// 3. load it, initialize consistently from the scene's [initial] and integrate to t_end with IDA
//    (KLU when the Jacobian is sparse), timed (best of several runs); steps and evaluations;
// 4. time one residual and one Jacobian evaluation at the consistent initial point;
// 5. with --handwritten: compile the hand-written header (docs/generated-code.md contract, same
//    state layout) with nhc::jit and the same flags and do 3 and 4 for it too, from the same
//    initial state, and report how far its final state is from the generated one's (the two
//    tables must be distinct: different addresses, else the comparison would be of one code);
//    the two integrations are then timed again alternating (at least 20 pairs or 2 s), and their
//    minima (wall and processor time) are the integration times reported.
// --opt, --translation-units, --unbounded-optimizer: how the generated header is compiled
// (nhc::jit::CompileOptions: flags taken as given, long_header_bytes = 0; translation_units;
// bounded_optimizer = false), to compare compile policies (bench/compile-time.md); the
// hand-written header is always compiled with the defaults.
// --quick: one run of everything (smoke test). bench/run.sh turns the JSON into bench/results.md.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/expr/common_arguments.hpp"
#include "nhc/expr/common_factors.hpp"
#include "nhc/expr/expression_dag.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct Options {
  std::string scene, out = "bench-out", model, jacobian = "auto", handwritten;
  std::vector<std::string> defines, opt;
  int translation_units = 0;
  bool unbounded_optimizer = false;
  double t_end = -1, rtol = -1, atol = -1;
  bool quick = false;
};

[[noreturn]] void usage(const std::string& message) {
  std::cerr << "nhc_bench: " << message << "\n"
            << "usage: nhc_bench SCENE --out DIR [--model M] [--jacobian auto|dense|sparse] [--t-end T]\n"
            << "                 [--rtol R] [--atol A] [--handwritten HEADER [--define NAME=VALUE]...] [--quick]\n"
            << "                 [--opt \"FLAGS\"] [--translation-units K] [--unbounded-optimizer]\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--out") o.out = value();
    else if (a == "--model") o.model = value();
    else if (a == "--jacobian") o.jacobian = value();
    else if (a == "--handwritten") o.handwritten = value();
    else if (a == "--define") o.defines.push_back(value());
    else if (a == "--t-end") o.t_end = std::stod(value());
    else if (a == "--rtol") o.rtol = std::stod(value());
    else if (a == "--atol") o.atol = std::stod(value());
    else if (a == "--quick") o.quick = true;
    else if (a == "--opt") {
      std::istringstream words(value());
      for (std::string w; words >> w;) o.opt.push_back(w);
    } else if (a == "--translation-units") o.translation_units = std::stoi(value());
    else if (a == "--unbounded-optimizer") o.unbounded_optimizer = true;
    else if (!a.empty() && a[0] == '-') usage("unknown option " + a);
    else if (o.scene.empty()) o.scene = a;
    else usage("more than one scene");
  }
  if (o.scene.empty()) usage("no scene");
  if (o.jacobian != "auto" && o.jacobian != "dense" && o.jacobian != "sparse") usage("bad --jacobian");
  return o;
}

/// Best time of `f` over repetitions: at least one, more while the total stays under `budget`
/// seconds (at most `max_runs`).
double best_time(const std::function<void()>& f, double budget, int max_runs) {
  double best = 1e300, total = 0;
  for (int run = 0; run < max_runs; ++run) {
    const auto start = Clock::now();
    f();
    const double s = seconds_since(start);
    best = std::min(best, s);
    total += s;
    if (total + s > budget) break;
  }
  return best;
}

/// Seconds per call of each of `fs`, from batches lasting at least `min_seconds`, the batches of
/// the different functions interleaved (so that a change of the machine's load hits all of them
/// alike); best of `rounds` batches each.
std::vector<double> per_call(const std::vector<std::function<void()>>& fs, double min_seconds, int rounds) {
  std::vector<long> calls(fs.size(), 1);
  for (size_t i = 0; i < fs.size(); ++i)
    for (;;) {
      const auto start = Clock::now();
      for (long k = 0; k < calls[i]; ++k) fs[i]();
      const double s = seconds_since(start);
      if (s >= min_seconds || calls[i] > (1L << 30)) break;
      calls[i] *= s > 0 ? std::max(2L, static_cast<long>(min_seconds / s * 1.2)) : 10;
    }
  std::vector<double> best(fs.size(), 1e300);
  for (int round = 0; round < rounds; ++round)
    for (size_t i = 0; i < fs.size(); ++i) {
      const auto start = Clock::now();
      for (long k = 0; k < calls[i]; ++k) fs[i]();
      best[i] = std::min(best[i], seconds_since(start) / static_cast<double>(calls[i]));
    }
  return best;
}

struct Json {
  std::ostringstream os;
  bool first = true;
  Json() {
    os.precision(9);
    os << "{";
  }
  void key(const std::string& k) {
    os << (first ? "" : ", ") << "\"" << k << "\": ";
    first = false;
  }
  void number(const std::string& k, double v) {
    key(k);
    if (std::isfinite(v)) os << v;
    else os << "null";
  }
  void integer(const std::string& k, long long v) {
    key(k);
    os << v;
  }
  void text(const std::string& k, const std::string& v) {
    key(k);
    os << "\"";
    for (char c : v) {
      if (c == '"' || c == '\\') os << '\\' << c;
      else if (static_cast<unsigned char>(c) < 0x20) os << ' ';
      else os << c;
    }
    os << "\"";
  }
  void raw(const std::string& k, const std::string& v) {
    key(k);
    os << v;
  }
  std::string str() { return os.str() + "}"; }
};

std::string address(const void* p) {
  char text[32];
  std::snprintf(text, sizeof text, "%p", p);
  return text;
}

std::string vector_json(const std::vector<double>& v) {
  std::ostringstream os;
  os.precision(17);
  os << "[";
  for (size_t i = 0; i < v.size(); ++i) os << (i ? ", " : "") << v[i];
  return os.str() + "]";
}

/// Per-function operation counts from the header's banner: "//   residual   45   30".
std::string banner_counts(const std::string& text) {
  std::istringstream in(text);
  std::string line, out = "{";
  bool inside = false, first = true;
  while (std::getline(in, line)) {
    if (line.rfind("//", 0) != 0) break;
    if (line.find("elimination:") != std::string::npos) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    std::istringstream fields(line.substr(2));
    std::string name;
    long before = 0, after = 0;
    if (fields >> name >> before >> after) {
      out += std::string(first ? "" : ", ") + "\"" + name + "\": [" + std::to_string(before) + ", " +
             std::to_string(after) + "]";
      first = false;
    }
  }
  return out + "}";
}

/// Operations after CSE of the residual and the Jacobian lowered into one DAG (one function
/// computing both, as sympy.cse of both lists does), without and with CSE; CSE is what the
/// header gets: hash-consing, common factors taken out of sums (common_factors.hpp), then common
/// pairs of operands shared (common_arguments.hpp, as sympy.cse's opt_cse).
std::pair<long long, long long> joint_residual_jacobian_ops(const nhc::Index1System& system) {
  const nhc::SymbolicJacobian jac = nhc::index1_jacobian(system);
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> in;
  in[system.jet->time()] = "t";
  for (size_t k = 0; k < system.jet->parameters().size(); ++k)
    in[system.jet->parameter(static_cast<int>(k))] = "p[" + std::to_string(k) + "]";
  // The inputs after the parameters (docs/generated-code.md, "Input additions"): the bicycle's Tphi.
  const std::size_t n_parameters = system.jet->parameters().size();
  for (std::size_t k = 0; k < system.jet->inputs().size(); ++k)
    in[system.jet->input(static_cast<int>(k))] = "p[" + std::to_string(n_parameters + k) + "]";
  for (size_t k = 0; k < system.y.size(); ++k) in[system.y[k]] = "y[" + std::to_string(k) + "]";
  for (size_t k = 0; k < system.yp.size(); ++k) in[system.yp[k]] = "yp[" + std::to_string(k) + "]";
  in[jac.cj] = "cj";
  nhc::ExpressionDag dag(in);
  std::vector<int> outputs;
  for (const auto& r : system.residuals) outputs.push_back(dag.add(r));
  for (const auto& e : jac.values)
    if (!e.is_zero()) outputs.push_back(dag.add(e));
  const long long before = nhc::tree_operation_count(dag, outputs).total();
  const nhc::ExpressionDag shared = nhc::share_common_arguments(nhc::factor_common_terms(dag, outputs), outputs);
  return {before, nhc::dag_operation_count(shared, outputs).total()};
}

struct Integration {
  nhc::runtime::RunResult run;
  double seconds = 0;
  double residual_seconds = 0, jacobian_seconds = 0;
  double cpu_seconds = 1e300;  ///< processor time of the best interleaved run (interleave_integrations)
  int repetitions = 0;         ///< interleaved runs
};

Integration integrate(const nhc::runtime::Model& model, const nhc::runtime::InitialState& initial, double t_end,
                      const nhc::runtime::IntegratorOptions& io, bool quick) {
  Integration out;
  const std::vector<double> p = model.default_parameters();
  const auto times = nhc::runtime::output_times(initial.t0, t_end, 10);
  out.seconds = best_time([&] { out.run = nhc::runtime::simulate(model, p, initial, times, io); }, quick ? 0 : 1.0,
                          quick ? 1 : 5);
  if (out.run.failure) throw std::runtime_error(std::string("integration failed: ") + out.run.failure->what());

  return out;
}

double process_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// The generated and the hand-written integrations again, alternating, for at least 2 s and 20
/// pairs (at most 1000): a change of the machine's load hits both alike. Their minima (wall and
/// processor time) replace the separate best-of-5 times.
void interleave_integrations(const nhc::runtime::Model& generated, const nhc::runtime::Model& handwritten,
                             const nhc::runtime::InitialState& initial, double t_end,
                             const nhc::runtime::IntegratorOptions& io, Integration& gen, Integration& hand) {
  const auto times = nhc::runtime::output_times(initial.t0, t_end, 10);
  const std::vector<double> pg = generated.default_parameters(), ph = handwritten.default_parameters();
  gen.seconds = hand.seconds = 1e300;
  const auto start = Clock::now();
  for (int pair = 0; pair < 1000 && (pair < 20 || seconds_since(start) < 2.0); ++pair) {
    for (int which = 0; which < 2; ++which) {
      // Alternate which goes first, so that neither always follows the other.
      const bool generated_turn = (which == 0) == (pair % 2 == 0);
      Integration& into = generated_turn ? gen : hand;
      const auto wall = Clock::now();
      const double cpu = process_seconds();
      const nhc::runtime::RunResult run = nhc::runtime::simulate(generated_turn ? generated : handwritten,
                                                                 generated_turn ? pg : ph, initial, times, io);
      into.seconds = std::min(into.seconds, seconds_since(wall));
      into.cpu_seconds = std::min(into.cpu_seconds, process_seconds() - cpu);
      into.repetitions += 1;
      if (run.failure) throw std::runtime_error(std::string("integration failed: ") + run.failure->what());
    }
  }
}

/// One residual and one Jacobian evaluation (the Jacobian the integrator uses) of each model at
/// the consistent initial point of its run, timed with all models interleaved.
void time_calls(const std::vector<const nhc::runtime::Model*>& models, const std::vector<Integration*>& runs,
                bool quick) {
  struct Buffers {
    std::vector<double> p, r, J;
  };
  std::vector<Buffers> buffers(models.size());
  std::vector<std::function<void()>> fs;
  const double cj = 1e3;
  for (size_t m = 0; m < models.size(); ++m) {
    const auto& t = models[m]->table();
    const int n = t.n_states;
    Buffers& b = buffers[m];
    b.p = models[m]->default_parameters();
    b.r.assign(static_cast<size_t>(n), 0.0);
    const double t0 = runs[m]->run.initial.t;
    const double* y = runs[m]->run.initial.y.data();
    const double* yp = runs[m]->run.initial.yp.data();
    fs.push_back([&t, &b, t0, y, yp] { t.residual(t0, y, yp, b.p.data(), b.r.data()); });
    // The Jacobian the integrator used in this model's run (its statistics say which): no size
    // policy of the bench's own (that lives in nhc::default_jacobian_kind).
    const std::string& used = runs[m]->run.statistics.jacobian;
    if (used == "generated sparse" || used == "generated sparse (scattered)") {
      b.J.assign(static_cast<size_t>(std::max(1, t.jacobian_nnz)), 0.0);
      fs.push_back([&t, &b, t0, y, yp, cj] { t.jacobian_values(t0, y, yp, cj, b.p.data(), b.J.data()); });
    } else {
      b.J.assign(static_cast<size_t>(n) * static_cast<size_t>(n), 0.0);
      fs.push_back([&t, &b, t0, y, yp, cj] {
        if (t.jacobian) t.jacobian(t0, y, yp, cj, b.p.data(), b.J.data());
      });
    }
  }
  const std::vector<double> seconds = per_call(fs, quick ? 1e-3 : 0.02, quick ? 1 : 9);
  for (size_t m = 0; m < models.size(); ++m) {
    runs[m]->residual_seconds = seconds[2 * m];
    runs[m]->jacobian_seconds =
        models[m]->table().jacobian || models[m]->table().jacobian_values ? seconds[2 * m + 1] : 0;
  }
}

void report_integration(Json& json, const std::string& prefix, const Integration& in) {
  const auto& st = in.run.statistics;
  json.number(prefix + "integrate_s", in.seconds);
  if (in.repetitions > 0) {
    json.number(prefix + "integrate_cpu_s", in.cpu_seconds);
    json.integer(prefix + "integrate_repetitions", in.repetitions);
  }
  json.integer(prefix + "steps", st.steps);
  json.integer(prefix + "residual_evaluations", st.residual_evaluations);
  json.integer(prefix + "jacobian_evaluations", st.jacobian_evaluations);
  json.integer(prefix + "nonlinear_iterations", st.nonlinear_iterations);
  json.integer(prefix + "error_test_failures", st.error_test_failures);
  json.text(prefix + "linear_solver", st.linear_solver);
  json.text(prefix + "jacobian", st.jacobian);
  json.number(prefix + "residual_call_s", in.residual_seconds);
  json.number(prefix + "jacobian_call_s", in.jacobian_seconds);
  json.number(prefix + "t_final", in.run.samples.empty() ? 0.0 : in.run.samples.back().t);
}

int run(const Options& o) {
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw std::runtime_error("cannot create " + o.out + ": " + ec.message());

  // 1. derive + analyse + generate.
  double load_s = 0, derive_s = 0, analyse_s = 0, generate_s = 0;
  nhc::GeneratedHeader header;
  int n_states = 0;
  std::pair<long long, long long> joint_ops;
  bool sparse = false;
  nhc::ModelKind kind_built = nhc::ModelKind::chetaev;
  auto pipeline = [&](bool record) {
    auto t0 = Clock::now();
    const nhc::Scene scene = nhc::load_scene(o.scene);
    const double a = seconds_since(t0);
    t0 = Clock::now();
    const nhc::ModelKind kind = nhc::model_or_default(scene, o.model);
    const nhc::DerivedModel derived = nhc::derive_model(scene, kind);
    if (!derived.applicable) throw std::runtime_error("model not applicable: " + derived.reason);
    const double b = seconds_since(t0);
    t0 = Clock::now();
    const nhc::Index1System system = nhc::reduce_to_index1(scene, derived);
    const double c = seconds_since(t0);
    t0 = Clock::now();
    nhc::HeaderOptions ho;
    ho.jacobian = o.jacobian == "auto"     ? nhc::default_jacobian_kind(system.size())
                  : o.jacobian == "sparse" ? nhc::JacobianKind::sparse
                                           : nhc::JacobianKind::dense;
    sparse = ho.jacobian == nhc::JacobianKind::sparse;
    nhc::GeneratedHeader h = nhc::generate_header(scene, system, ho);
    const double d = seconds_since(t0);
    if (record || a + b + c + d < load_s + derive_s + analyse_s + generate_s) {
      load_s = a, derive_s = b, analyse_s = c, generate_s = d;
    }
    if (record) {
      header = std::move(h);
      n_states = system.size();
      kind_built = kind;
      joint_ops = joint_residual_jacobian_ops(system);
    }
  };
  pipeline(true);
  if (!o.quick) {
    double total = load_s + derive_s + analyse_s + generate_s, spent = total;
    for (int k = 0; k < 4 && spent + total < 1.0; ++k) {
      pipeline(false);
      spent += total;
    }
  }

  const std::string header_path = (fs::path(o.out) / header.file_name).string();
  {
    std::ofstream f(header_path);
    f << header.text;
    if (!f) throw std::runtime_error("cannot write " + header_path);
  }

  // 2. compile (nhc::jit, in a cache of this run's own: a compile, not a cache hit).
  nhc::jit::CompileOptions compile_options;
  compile_options.cache_directory = fs::path(o.out) / "jit-cache";
  fs::remove_all(compile_options.cache_directory, ec);
  nhc::jit::CompileOptions generated_options = compile_options;
  if (!o.opt.empty()) {
    generated_options.flags = o.opt;
    generated_options.long_header_bytes = 0;  // as given
  }
  generated_options.translation_units = o.translation_units;
  generated_options.bounded_optimizer = !o.unbounded_optimizer;
  const nhc::jit::LoadedModel loaded = nhc::jit::load_header(
      header, kind_built, sparse ? nhc::JacobianKind::sparse : nhc::JacobianKind::dense, generated_options);
  const double compile_s = loaded.library().seconds;
  const std::string model_name = nhc::to_string(kind_built);

  // 3, 4. integrate.
  const nhc::Scene scene = nhc::load_scene(o.scene);
  const nhc::runtime::Model& model = loaded.model();
  const nhc::runtime::InitialState initial =
      nhc::runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
  nhc::runtime::IntegratorOptions io;
  io.rtol = o.rtol > 0 ? o.rtol : scene.simulate.rtol;
  io.atol = o.atol > 0 ? o.atol : scene.simulate.atol;
  // Both models (generated, hand-written) on the linear solver of the generated header's Jacobian
  // kind (nhc::default_jacobian_kind unless --jacobian), so that they are compared on equal terms.
  io.linear_solver = sparse ? nhc::runtime::LinearSolverKind::sparse : nhc::runtime::LinearSolverKind::dense;
  const double t_end = o.t_end > 0 ? o.t_end : scene.simulate.t_end;
  Integration gen = integrate(model, initial, t_end, io, o.quick);
  std::optional<nhc::runtime::Model> hw;
  Integration hand;
  double hw_compile_s = 0;
  std::string hw_library_name;
  if (!o.handwritten.empty()) {
    nhc::jit::CompileOptions hw_options = compile_options;
    for (const std::string& d : o.defines) hw_options.flags.push_back("-D" + d);
    const nhc::jit::CompiledLibrary hw_library = nhc::jit::compile_header_file(o.handwritten, hw_options);
    hw_compile_s = hw_library.seconds;
    hw_library_name = hw_library.path.filename().string();
    hw = nhc::runtime::Model::load(hw_library.path.string());
    if (&hw->table() == &model.table())
      throw std::runtime_error(
          "the hand-written and the generated model share one table: the comparison would be "
          "of one code with itself");
    if (hw->n_states() != model.n_states())
      throw std::runtime_error("the hand-written model has " + std::to_string(hw->n_states()) +
                               " states, the generated " + std::to_string(model.n_states()));
    for (int i = 0; i < hw->n_states(); ++i)
      if (hw->state_name(i) != model.state_name(i))
        throw std::runtime_error("state " + std::to_string(i) + " is " + hw->state_name(i) + " hand-written, " +
                                 model.state_name(i) + " generated");
    hand = integrate(*hw, initial, t_end, io, o.quick);
    if (!o.quick) interleave_integrations(model, *hw, initial, t_end, io, gen, hand);
    time_calls({&model, &*hw}, {&gen, &hand}, o.quick);
  } else {
    time_calls({&model}, {&gen}, o.quick);
  }

  Json json;
  json.text("scene", scene.name);
  json.text("model", model_name);
  json.integer("n_states", n_states);
  json.integer("n_coordinates", model.n_coordinates());
  json.integer("n_multipliers", model.n_multipliers());
  json.text("jacobian_kind", sparse ? "sparse" : "dense");
  json.integer("sparse_jacobian_from_states", nhc::kSparseJacobianFromStates);
  json.integer("jacobian_nnz", model.table().jacobian_nnz);
  json.number("load_s", load_s);
  json.number("derive_s", derive_s);
  json.number("analyse_s", analyse_s);
  json.number("generate_s", generate_s);
  json.number("derive_analyse_generate_s", load_s + derive_s + analyse_s + generate_s);
  json.integer("ops_before_cse", header.before_cse.total());
  json.integer("ops_after_cse", header.after_cse.total());
  json.raw("ops_by_function", banner_counts(header.text));
  json.integer("residual_jacobian_joint_ops_before_cse", joint_ops.first);
  json.integer("residual_jacobian_joint_ops_after_cse", joint_ops.second);
  json.integer("header_bytes", static_cast<long long>(header.text.size()));
  json.number("compile_s", compile_s);
  json.integer("translation_units", loaded.library().translation_units);
  json.number("rtol", io.rtol);
  json.number("atol", io.atol);
  json.number("t_end", t_end);
  report_integration(json, "", gen);
  const std::vector<double> final_y = gen.run.samples.back().y;
  json.raw("final_state_names", [&] {
    std::string s = "[";
    for (int i = 0; i < model.n_states(); ++i) s += (i ? ", \"" : "\"") + model.state_name(i) + "\"";
    return s + "]";
  }());
  json.raw("final_y", vector_json(final_y));

  // 5. the hand-written limit.
  if (hw) {
    json.number("handwritten_compile_s", hw_compile_s);
    json.text("handwritten_library", hw_library_name);
    json.text("generated_library", fs::path(loaded.library().path).filename().string());
    // Two distinct objects, not one table reached twice (GNU_UNIQUE aliasing): the bench refused
    // above if the addresses were equal; they are recorded for bench/results.md.
    json.text("generated_table_address", address(&model.table()));
    json.text("handwritten_table_address", address(&hw->table()));
    report_integration(json, "handwritten_", hand);
    double diff = 0, scale = 0;
    const std::vector<double>& hy = hand.run.samples.back().y;
    for (int i = 0; i < model.n_states(); ++i)
      if (model.is_differential(i)) {
        diff = std::max(diff, std::abs(hy[static_cast<size_t>(i)] - final_y[static_cast<size_t>(i)]));
        scale = std::max(scale, std::abs(final_y[static_cast<size_t>(i)]));
      }
    json.number("handwritten_final_difference", diff);
    json.number("final_state_scale", scale);
  }
  std::cout << json.str() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::cerr << "nhc_bench: error: " << e.what() << "\n";
    return 1;
  }
}
