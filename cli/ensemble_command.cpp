// nhc ensemble SCENE [--model M] --vary NAME=a:b:n [--vary …]
//                    | --sample NAME=uniform(a,b)|normal(m,s) [--sample …] --samples N --seed S
//              [--t-end T] [--initial NAME=VALUE]... [--outputs K] [--keep trajectories|final] [--resume] [--plot
//              OUTCOME]
//              [--threads N] -o FILE.h5
//
// Many runs of one model (docs/ensemble.md). Rank 0 derives and compiles the model once through
// nhc::jit; the other ranks load the same shared object. Runs are handed out dynamically
// (nhc/ensemble/scheduler.hpp) to the MPI ranks under mpirun, else to threads of this process.
// Every run's outcome, final state, drift and statistics go to FILE.h5 (HDF5), which is
// checkpointed while the ensemble runs so that --resume continues a killed one.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>
#include <thread>

#include <unistd.h>

#include "nhc/app/parameter_values.hpp"
#include "nhc/app/run_engine.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/app/scene_runs.hpp"
#include "nhc/app/switched_run.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/long_work.hpp"
#include "command_programs.hpp"
#include "commands.hpp"
#include "failure_report.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "flag_rules.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/tools/sha256.hpp"
#include "nhc/errors.hpp"
#include "nhc/base/clock.hpp"
#include "nhc/base/number_text.hpp"
#include "run_flags.hpp"

#ifdef NHC_HAVE_ENSEMBLE
#include <filesystem>
#include <memory>

#include "nhc/ensemble.hpp"
#include "nhc/jit.hpp"
#endif

namespace nhc::cli {

namespace {

struct EnsembleOptions {
  std::string scene_path, model, output, keep = "final", plot;
  std::vector<std::string> vary, sample;
  std::vector<std::string> initial;  ///< --initial NAME=VALUE
  std::optional<long> samples;
  std::uint64_t seed = 0;
  std::optional<double> t_end, rtol, atol;
  std::optional<int> outputs;  ///< default 100 (none under a sampled controller: its samples)
  int threads = 0;
  double checkpoint_seconds = 10;
  bool resume = false;
};

#ifndef NHC_HAVE_ENSEMBLE

int run_ensemble(const EnsembleOptions&) {
  std::cerr << "nhc: error: nhc ensemble needs HDF5, which was not found when nhc was built: install Debian's "
               "libhdf5-dev (and libopenmpi-dev openmpi-bin for MPI; scripts/setup.sh installs them) and configure "
               "again (cmake -S . -B build)\n";
  return kExitInternal;
}

#else

using namespace nhc::ensemble;

/// What every rank runs: the scene (the text rank 0 read, with the --initial values), the
/// compiled model and the sliding model of a contact that slides, loaded from the shared objects
/// rank 0 built, and the runs of the one run engine on them (app::SceneRuns).
struct Members {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<runtime::Model> model, sliding;  ///< loaded (workers); null on rank 0 (its builds hold them)
  std::unique_ptr<app::SceneRuns> runs;
};

/// What rank 0 prepares before any run: the model, the design, the settings, earlier records.
struct Prepared {
  std::unique_ptr<jit::LoadedModel> built, sliding;
  Members members;
  RunSpec spec;
  EnsembleResults results;
  std::vector<std::int64_t> todo;
  double build_seconds = 0;
};

[[noreturn]] void bad_flag(const std::string& where, const std::string& why) { throw InputError({where, 0, 0}, why); }

/// The flags on their own, before the scene is read.
void check_flags(const EnsembleOptions& o) {
  if (o.output.empty()) bad_flag("-o", "nhc ensemble needs -o FILE.h5");
  if (o.vary.empty() && o.sample.empty()) bad_flag("--vary", "nhc ensemble needs --vary NAME=a:b:n or --sample NAME=…");
  if (!o.vary.empty() && !o.sample.empty())
    bad_flag("--sample " + o.sample.front(), "--vary (a grid) and --sample (a random design) do not mix");
  if (!o.sample.empty() && !o.samples) bad_flag("--sample " + o.sample.front(), "--sample needs --samples N");
  if (o.sample.empty() && o.samples) bad_flag("--samples", "--samples needs --sample NAME=…");
  if (o.keep != "final" && o.keep != "trajectories") bad_flag("--keep " + o.keep, "expected trajectories or final");
  if (o.threads < 0) bad_flag("--threads " + std::to_string(o.threads), "N must be at least 1 (0: all cores)");
}

Design make_design(const EnsembleOptions& o) {
  std::vector<VariableSpec> specs;
  for (const std::string& v : o.vary) specs.push_back(parse_vary(v));
  for (const std::string& s : o.sample) specs.push_back(parse_sample(s));
  return o.vary.empty() ? make_sample(std::move(specs), *o.samples, o.seed) : make_grid(std::move(specs));
}

/// Earlier records of the same ensemble (--resume), else all pending.
std::vector<RunRecord> earlier_records(const EnsembleOptions& o, const EnsembleInfo& info) {
  if (o.resume && std::filesystem::exists(o.output)) {
    EnsembleResults stored = read_results(o.output);
    const std::string why = resume_mismatch(stored.info, info);
    if (!why.empty())
      bad_flag("--resume", o.output + " holds a different ensemble (" + why + "); remove it or leave out --resume");
    return std::move(stored.records);
  }
  std::vector<RunRecord> records;
  for (long k = 0; k < info.design.runs; ++k)
    records.push_back(
        pending_record(k, static_cast<int>(info.state_names.size()), static_cast<int>(info.invariant_names.size())));
  return records;
}

/// The number of runs the design flags ask for, before any value is made: a grid's product of n
/// (saturating), or --samples.
double requested_runs(const EnsembleOptions& o) {
  if (o.vary.empty()) return o.samples ? static_cast<double>(*o.samples) : 0.0;
  double runs = 1;
  for (const std::string& v : o.vary) runs *= static_cast<double>(parse_vary(v).n);
  return runs;
}

/// The design flags as written, for messages.
std::string design_flags(const EnsembleOptions& o) {
  std::string flags;
  for (const std::string& v : o.vary) flags += (flags.empty() ? "--vary " : " --vary ") + v;
  if (o.vary.empty() && o.samples) flags = "--samples " + std::to_string(*o.samples);
  return flags;
}

/// Refuses, before anything runs, a design whose results cannot fit: the result file (values,
/// outcome, final state, drifts and, with --keep trajectories, every output row of every run)
/// against the free space of the disk it goes to, and the same records in memory against the
/// machine's memory. Both are estimates from the sizes of the records (ensemble/run.hpp), which
/// is what grows with the number of runs.
void check_design_fits(const EnsembleOptions& o, int outputs, int n_states, int n_invariants, bool keep_trajectories) {
  const double runs = requested_runs(o);
  const double variables = static_cast<double>(o.vary.size() + o.sample.size());
  const double trajectory = keep_trajectories ? 8.0 * (outputs + 1) * n_states : 0.0;
  const double file_per_run = 8.0 * (variables + n_states + n_invariants + 6) + trajectory;
  const double memory_per_run = sizeof(RunRecord) + 8.0 * (variables + n_states + n_invariants) + 64 + trajectory;
  const double file_bytes = runs * file_per_run, memory_bytes = runs * memory_per_run;
  auto bytes_text = [](double b) {
    const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
    int u = 0;
    while (b >= 1000 && u < 5) b /= 1000, ++u;
    return base::number_text(b, 3) + " " + units[u];
  };
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::absolute(o.output).parent_path();
  const std::filesystem::space_info disk = std::filesystem::space(dir, ec);
  if (!ec && file_bytes > static_cast<double>(disk.available))
    bad_flag(design_flags(o), base::number_text(runs, 4) + " runs would write about " + bytes_text(file_bytes) +
                                  " to " + o.output + ", and " + bytes_text(static_cast<double>(disk.available)) +
                                  " are free there; make the design smaller");
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  const double memory = pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0;
  if (memory > 0 && memory_bytes > 0.5 * memory)
    bad_flag(design_flags(o), base::number_text(runs, 4) + " runs would hold about " + bytes_text(memory_bytes) +
                                  " of results in memory, and the machine has " + bytes_text(memory) +
                                  "; make the design smaller" +
                                  (keep_trajectories ? " or keep fewer outputs (--outputs)" : ""));
}

/// The settings every run shares: --t-end, --rtol, --atol, --outputs (default 100; a sampled
/// controller's rows are its samples), in the command line's words located at the scene.
app::RunRequest run_request(const EnsembleOptions& o, const Scene& scene) {
  app::RunRequest request;
  request.t_end = o.t_end;
  request.rtol = o.rtol;
  request.atol = o.atol;
  if (o.outputs) request.outputs = *o.outputs;
  else if (!scene.controller.present) request.outputs = 100;
  return request;
}

app::FieldNames field_names(const EnsembleOptions& o) {
  app::FieldNames names = app::command_line_names();
  names.at = o.scene_path;
  return names;
}

/// The scene of the runs from its text, with the --initial values (every rank: the same text).
std::unique_ptr<Scene> members_scene(const std::string& text, const EnsembleOptions& o) {
  auto scene = std::make_unique<Scene>(parse_scene(text, o.scene_path));
  apply_initial_flags(*scene, o.initial);
  return scene;
}

/// The design variable as the run sets it: a parameter of the scene (as --set), or an initial
/// value x'(0) (as --initial). Refused, at the flag: a parameter that places the runs in time or
/// sets their accuracy (the runs share their output times and tolerances), one nothing reads.
Target design_target(const Scene& scene, const runtime::Model& model, const std::string& name,
                     const std::string& flag) {
  std::vector<std::string> parameters;
  for (int k = 0; k < model.n_parameters(); ++k) parameters.push_back(model.table().parameter_names[k]);
  if (!scene.jet->parameter_index(name)) return resolve_initial_target(model, parameters, name, flag);
  if (const std::vector<std::string> numbers = app::run_grid_numbers_using(scene, name); !numbers.empty())
    bad_flag(flag, "the scene's " + numbers.front() + " is written through '" + name +
                       "', which the runs of nhc ensemble share (they are compared on the same output times, "
                       "at the same tolerances): run nhc simulate --set " +
                       name + "=… for each value");
  // Read by the equations, by [initial] (each run's start moves), by an event, a contact or the
  // controller (each run evaluates them at its values): else varying it would change nothing.
  const std::vector<double> slopes = app::initial_slopes(scene, model, name);
  const bool moves_start = std::any_of(slopes.begin(), slopes.end(), [](double s) { return s != 0; });
  if (!moves_start && app::run_places_reading(scene, name).empty())
    app::refuse_unread_parameter(scene, model, name, flag, "varying it would change nothing");
  Target target;
  target.kind = Target::Kind::parameter;
  target.name = name;
  return target;
}

/// One run's values as --set and --initial give them.
app::RunValues run_values(const RunSpec& spec, const double* values) {
  app::RunValues v;
  for (std::size_t k = 0; k < spec.targets.size(); ++k) {
    const Target& t = spec.targets[k];
    if (t.kind == Target::Kind::parameter) v.parameters.emplace_back(t.name, values[k]);
    else
      v.initial.push_back(
          {base::primed_name(t.variable, t.order), values[k], base::primed_name(t.variable, t.order) + "(0)"});
  }
  return v;
}

Prepared prepare(const EnsembleOptions& o, int ranks, int threads) {
  const auto start = base::Clock::now();
  check_flags(o);
  for (const std::string& v : o.vary) parse_vary(v);  // a malformed flag first, before any estimate
  // Before the design's values are made: at least one state per run.
  const int outputs = o.outputs.value_or(100);
  check_design_fits(o, outputs, 1, 0, o.keep == "trajectories");
  Design design = make_design(o);
  Prepared p;
  p.members.scene = std::make_unique<Scene>(load_scene(o.scene_path));
  apply_initial_flags(*p.members.scene, o.initial);
  const Scene& scene = *p.members.scene;
  app::refuse_many_runs_of_mpc(scene, "nhc ensemble");
  const ModelKind kind = model_or_default(scene, o.model);
  app::require_model_inputs(scene, kind);
  // The rules of a run (app/run_request.hpp) and the engine's refusals (app/run_engine.hpp), as
  // nhc simulate's: the runs are nhc simulate's runs.
  const app::RunRequest request = run_request(o, scene);
  const app::FieldNames fields = field_names(o);
  app::check_run_request(request, scene, kind, fields);
  app::RunFeatures features;
  features.controller = scene.controller.present;
  features.controller_name = "the scene's [controller]";
  features.controller_where = scene.controller.where.str();
  features.outputs = o.outputs.has_value();
  app::check_run_features(scene, features, fields);
  const double t0 = scene.initial.t0, t_end = app::run_t_end(scene, o.t_end, "--t-end");
  if (!scene.controller.present)
    flag_rules::output_times(t0, t_end, outputs, "--t-end/--outputs");  // they must not collapse
  check_output_file(o.output, {o.scene_path});
  check_writable(o.output);

  p.built = std::make_unique<jit::LoadedModel>(jit::build(scene, kind));
  const runtime::Model& model = p.built->model();
  // A contact that slides: its sliding model, one for every run (a mu written through the
  // parameters is read at run time).
  if (const SceneContact* slide = app::sliding_contact(scene))
    p.sliding = std::make_unique<jit::LoadedModel>(app::build_sliding_model(scene, *slide, kind, {}));
  p.members.runs =
      std::make_unique<app::SceneRuns>(scene, model, p.sliding ? &p.sliding->model() : nullptr, request, fields);
  const std::vector<double>& times = p.members.runs->times();
  check_design_fits(o, static_cast<int>(times.size()) - 1, model.n_states(), model.n_invariants(),
                    o.keep == "trajectories");
  RunSpec& spec = p.spec;
  spec.shared_object = p.built->library().path.string();
  if (p.sliding) spec.sliding_object = p.sliding->library().path.string();
  spec.scene_text = scene.source_text();
  spec.t0 = t0;
  spec.t_end = t_end;
  spec.outputs = static_cast<std::int32_t>(times.size()) - 1;
  spec.period = scene.controller.present ? scene.controller.period : 0.0;
  spec.rtol = o.rtol.value_or(scene.simulate.rtol);
  spec.atol = o.atol.value_or(scene.simulate.atol);
  spec.keep_trajectories = o.keep == "trajectories";
  if (spec.times() != times) throw std::logic_error("nhc ensemble: the runs' times differ from the file's");
  for (const VariableSpec& v : design.variables)
    spec.targets.push_back(design_target(scene, model, v.name, (o.vary.empty() ? "--sample " : "--vary ") + v.text));

  EnsembleInfo& info = p.results.info;
  info.scene = scene.name;
  info.scene_file = o.scene_path;
  // The runs start from the scene's [initial] with the --initial values: --resume continues only
  // an ensemble computed from the same ones (the text alone when there are none, as before).
  std::string computed_from = scene.source_text();
  for (const std::string& a : o.initial) computed_from += "\n--initial " + a;
  info.scene_digest = tools::sha256_hex(computed_from);
  info.model = to_string(kind);
  info.nhc_version = NHC_VERSION;
  info.rtol = spec.rtol;
  info.atol = spec.atol;
  info.t0 = t0;
  info.t_end = t_end;
  info.outputs = spec.outputs;
  info.period = spec.period;
  info.keep_trajectories = spec.keep_trajectories;
  for (int i = 0; i < model.n_states(); ++i) info.state_names.push_back(model.state_name(i));
  for (int k = 0; k < model.n_invariants(); ++k) info.invariant_names.push_back(model.table().invariant_names[k]);
  info.design = std::move(design);
  info.ranks = ranks;
  info.threads = threads;
  if (!o.plot.empty()) {
    const std::vector<std::string> names = outcome_names(info);
    if (std::find(names.begin(), names.end(), o.plot) == names.end())
      outcome_values(EnsembleResults{info, {}}, o.plot, "--plot");  // throws, naming the outcomes
    if (info.design.variables.size() > 2)
      bad_flag("--plot " + o.plot, "maps need a design of one or two variables, this one has " +
                                       std::to_string(info.design.variables.size()));
  }
  p.results.records = earlier_records(o, info);
  for (const RunRecord& r : p.results.records)
    if (!r.finished()) p.todo.push_back(r.index);
  p.build_seconds = base::seconds_since(start);
  return p;
}

/// The symbolic lock of the worker threads (nhc/long_work.hpp): GiNaC's reference counts are not
/// synchronised, so one thread at a time makes or releases expressions. Recursive: an expression
/// a run evaluates with GiNaC takes it again inside the engine's own section.
class ThreadSymbolicLock final : public SymbolicLock {
 public:
  void lock() override { mutex_.lock(); }
  void unlock() override { mutex_.unlock(); }

 private:
  std::recursive_mutex mutex_;
};

/// Installs a symbolic lock while it lives (none after).
class InstalledSymbolicLock {
 public:
  explicit InstalledSymbolicLock(SymbolicLock& lock) { set_symbolic_lock(&lock); }
  ~InstalledSymbolicLock() { set_symbolic_lock(nullptr); }
  InstalledSymbolicLock(const InstalledSymbolicLock&) = delete;
  InstalledSymbolicLock& operator=(const InstalledSymbolicLock&) = delete;
};

/// Keeps FILE.h5 current while the ensemble runs: a checkpoint every `interval` seconds, or
/// rarer when writing takes long (at most 5 % of the time goes to checkpoints).
class Checkpoints {
 public:
  Checkpoints(const std::string& path, EnsembleResults& results, double interval)
      : path_(path), results_(results), interval_(interval) {}
  void maybe_write() {
    if (!dirty_ || base::seconds_since(last_) < std::max(interval_, 20.0 * last_write_seconds_)) return;
    const auto start = base::Clock::now();
    write_results(path_, results_);
    last_write_seconds_ = base::seconds_since(start);
    last_ = base::Clock::now();
    dirty_ = false;
  }
  void touched() { dirty_ = true; }

 private:
  std::string path_;
  EnsembleResults& results_;
  double interval_;
  base::Clock::time_point last_ = base::Clock::now();
  double last_write_seconds_ = 0;
  bool dirty_ = false;
};

/// Says once, when the first runs are in (after 2 s), how long the rest will take at their pace,
/// unless the rest is short.
class TimeEstimate {
 public:
  explicit TimeEstimate(long runs) : runs_(runs) {}
  void finished(long count) {
    done_ += count;
    if (said_ || done_ < 1) return;
    const double elapsed = base::seconds_since(start_);
    if (elapsed < 2.0) return;
    said_ = true;
    const double rest = elapsed * static_cast<double>(runs_ - done_) / static_cast<double>(done_);
    if (rest > 10.0)
      std::cerr << "nhc ensemble: " << done_ << " of " << runs_ << " runs in " << base::number_text(elapsed, 3)
                << " s; at that pace about " << base::number_text(rest, 3) << " s to go\n";
  }

 private:
  long runs_, done_ = 0;
  bool said_ = false;
  base::Clock::time_point start_ = base::Clock::now();
};

void print_summary(const EnsembleResults& r, const Prepared& p, long ran, double run_seconds, int workers,
                   const std::string& output) {
  long count[5] = {0, 0, 0, 0, 0};
  for (const RunRecord& rec : r.records) ++count[static_cast<int>(rec.outcome)];
  double integration = 0;  // of the runs made now (not those resumed from the file)
  for (std::int64_t i : p.todo) integration += r.records[static_cast<std::size_t>(i)].seconds;
  const EnsembleInfo& i = r.info;
  std::cout << "nhc ensemble: " << i.scene << ", model " << i.model << ", " << i.design.runs << " runs ("
            << (i.design.kind == Design::Kind::grid ? "grid" : "sample") << " of " << i.design.variables.size()
            << " variable" << (i.design.variables.size() == 1 ? "" : "s") << "), t from " << i.t0 << " to " << i.t_end
            << "\n  " << count[1] << " ok, " << count[4] << " ended by an event, " << count[2]
            << " stopped at a singular point, " << count[3] << " failed";
  if (count[0] > 0) std::cout << ", " << count[0] << " not run";
  std::cout << "\n  ran " << ran << " (" << (i.design.runs - ran) << " finished before) on " << i.ranks << " rank"
            << (i.ranks == 1 ? "" : "s") << " x " << i.threads << " thread" << (i.threads == 1 ? "" : "s") << "; build "
            << base::number_text(p.build_seconds, 3) << " s, runs " << base::number_text(run_seconds, 3) << " s";
  if (ran > 0 && run_seconds > 0) {
    const double per_run = integration / ran, overhead = std::max(0.0, run_seconds * workers - integration) / ran;
    std::cout << " (" << base::number_text(ran / run_seconds, 4) << " runs/s; per run: integration "
              << base::number_text(per_run * 1e3, 4) << " ms, overhead " << base::number_text(overhead * 1e3, 3)
              << " ms = " << base::number_text(100 * overhead / per_run, 3) << " %)";
  }
  if (i.ranks > 1) {  // how the dynamic scheduling spread the runs made now
    std::vector<long> per_rank(static_cast<std::size_t>(i.ranks), 0);
    for (std::int64_t k : p.todo) {
      const int rank = r.records[static_cast<std::size_t>(k)].rank;
      if (rank >= 0 && rank < i.ranks) ++per_rank[static_cast<std::size_t>(rank)];
    }
    std::cout << "\n  runs per rank:";
    for (std::size_t k = 0; k < per_rank.size(); ++k) std::cout << (k ? ", " : " ") << per_rank[k];
  }
  std::cout << "\n  wrote " << output << "\n";
}

int run_ensemble(const EnsembleOptions& o) {
  Session session;
  // At most a thread per core: more only share the cores and cost a stack each.
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = session.uses_mpi() ? 1 : o.threads > 0 ? std::min(o.threads, cores) : cores;
  if (!session.uses_mpi() && o.threads > cores && session.is_root())
    std::cerr << "nhc ensemble: --threads " << o.threads << " capped at the " << cores << " cores of this machine\n";
  Prepared p;
  int status = kExitOk;
  if (session.is_root()) {
    try {
      p = prepare(o, session.size(), threads);
    } catch (...) {
      status = report_failure(std::current_exception());
    }
  }
  status = session.broadcast(status);
  if (status != kExitOk) return status;

  // Every rank integrates the same shared objects; only rank 0 derived and compiled them. The
  // workers read the scene from the text rank 0 read.
  std::vector<char> bytes;
  if (session.is_root()) bytes = encode(p.spec);
  session.broadcast(bytes);
  const RunSpec spec = session.is_root() ? p.spec : decode_spec(bytes);
  Members& members = p.members;
  if (!session.is_root()) {
    try {
      members.scene = members_scene(spec.scene_text, o);
      members.model = std::make_unique<runtime::Model>(runtime::Model::load(spec.shared_object));
      if (!spec.sliding_object.empty())
        members.sliding = std::make_unique<runtime::Model>(runtime::Model::load(spec.sliding_object));
      members.runs = std::make_unique<app::SceneRuns>(*members.scene, *members.model, members.sliding.get(),
                                                      run_request(o, *members.scene), field_names(o));
      if (members.runs->times() != spec.times())
        throw std::logic_error("nhc ensemble: a worker's run times differ from rank 0's");
    } catch (...) {
      const int code = report_failure(std::current_exception());
      session.abort(code);  // rank 0 would wait for this worker for ever
      return code;
    }
  }
  const runtime::Model& model = session.is_root() ? p.built->model() : *members.model;
  // The worker threads do symbolic work (each run's scene, events, contact and controller laws):
  // one at a time (nhc/long_work.hpp).
  ThreadSymbolicLock symbolic_lock;
  const InstalledSymbolicLock installed(symbolic_lock);

  EnsembleResults& results = p.results;
  Checkpoints checkpoints(o.output, results, o.checkpoint_seconds);
  ScheduleOptions schedule_options;
  schedule_options.threads =
      static_cast<int>(std::clamp<std::int64_t>(static_cast<std::int64_t>(p.todo.size()), 1, threads));
  schedule_options.values_per_run = static_cast<int>(spec.targets.size());
  schedule_options.values = [&results](std::int64_t i) { return results.info.design.row(i); };
  TimeEstimate estimate(static_cast<long>(p.todo.size()));
  schedule_options.on_records = [&](std::vector<RunRecord>&& records) {
    estimate.finished(static_cast<long>(records.size()));
    for (RunRecord& r : records) results.records[static_cast<std::size_t>(r.index)] = std::move(r);
    checkpoints.touched();
  };
  schedule_options.on_idle = [&] { checkpoints.maybe_write(); };
  const auto start = base::Clock::now();
  // Each run is nhc simulate's run at its values, through the one run engine (app::SceneRuns).
  const MemberFunction member = [&members, &spec](const double* values) {
    app::SceneRun made = members.runs->run(run_values(spec, values));
    return MemberRun{std::move(made.outcome.run), std::move(made.outcome.drift_samples), std::move(made.p)};
  };
  const RunFunction run = [&model, &spec, &member](std::int64_t index, const double* values) {
    return run_one(model, spec, index, values, member);
  };
  try {
    schedule(session, p.todo, run, schedule_options);
    if (!session.is_root()) return kExitOk;
    results.info.wall_seconds = base::seconds_since(start);
    write_results(o.output, results);
  } catch (...) {
    const int code = report_failure(std::current_exception());
    session.abort(code);  // under MPI: the workers would wait for rank 0 for ever
    return code;
  }
  const int workers = session.uses_mpi() ? session.size() : threads;
  print_summary(results, p, static_cast<long>(p.todo.size()), results.info.wall_seconds, workers, o.output);
  if (!o.plot.empty())
    for (const std::string& image :
         plot_outcome(results, o.plot, default_plot_stem(o.output, o.plot), "--plot", {o.scene_path, o.output}))
      std::cout << "  wrote " << image << "\n";
  return kExitOk;
}

#endif

}  // namespace

CommandRunner add_ensemble_command(CLI::App& app) {
  auto o = std::make_shared<EnsembleOptions>();
  CLI::App* sub = app.add_subcommand("ensemble", command_description("ensemble"));
  sub->add_option("SCENE", o->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", o->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--vary", o->vary,
                  "NAME=a:b:n: n values from a to b (a parameter, or an initial value x'(0)); "
                  "repeated: the Cartesian product")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--sample", o->sample, "NAME=uniform(a,b) or NAME=normal(m,s): a random design (repeatable)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--samples", o->samples, "N: number of random samples");
  sub->add_option("--seed", o->seed, "S: the seed fixing every sample (default 0)");
  sub->add_option("--t-end", o->t_end, "final time (default: [simulate] t_end)")->check(flag_rules::finite());
  sub->add_option("--rtol", o->rtol, "relative tolerance (default: [simulate] rtol)")
      ->check(flag_rules::relative_tolerance());
  sub->add_option("--atol", o->atol, "absolute tolerance (default: [simulate] atol)")
      ->check(flag_rules::absolute_tolerance());
  add_initial_flag(sub, o->initial);
  sub->add_option("--outputs", o->outputs, "K: output intervals per run, for drift and trajectories (default 100)")
      ->check(flag_rules::count(1, flag_rules::kMaxOutputs));
  sub->add_option("--keep", o->keep, "final (default): final states only; trajectories: also the sampled states");
  sub->add_option("-o,--output", o->output, "FILE.h5, the results (HDF5)");
  sub->add_flag("--resume", o->resume, "continue the ensemble in FILE.h5: skip its finished runs");
  sub->add_option("--plot", o->plot, "OUTCOME (t_stop, final:x, drift:energy, …): also draw FILE_OUTCOME.svg/.png");
  sub->add_option("--checkpoint-every", o->checkpoint_seconds,
                  "S: rewrite FILE.h5 every S seconds while running (default 10)")
      ->check(flag_rules::positive());
  sub->add_option("--threads", o->threads, "worker threads without mpirun (default 0: all cores)");
  return [o]() { return run_ensemble(*o); };
}

}  // namespace nhc::cli
