// The ensemble's HDF5 file (results_file.hpp).
#include "nhc/ensemble/results_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>

#include "nhc/io/input_file.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/parent_directories.hpp"

namespace nhc::ensemble {

long EnsembleResults::finished() const {
  return static_cast<long>(
      std::count_if(records.begin(), records.end(), [](const RunRecord& r) { return r.finished(); }));
}

namespace {

/// A failed HDF5 call. Why, as far as HDF5's error stack tells: memory or another resource of the
/// machine (H5E_RESOURCE), no reason at all (out of memory, HDF5 cannot even record one: seen
/// under `ulimit -v`), or a wrong call of nhc's (anything else: a bug).
class Hdf5Failure : public std::runtime_error {
 public:
  enum class Cause { resource, unrecorded, call };
  Hdf5Failure(const std::string& what, Cause cause) : std::runtime_error("HDF5: cannot " + what), cause_(cause) {}
  Cause cause() const noexcept { return cause_; }

 private:
  Cause cause_;
};

struct StackReading {
  int entries = 0;
  bool resource = false;
};

herr_t read_entry(unsigned, const H5E_error2_t* entry, void* reading) {
  auto& r = *static_cast<StackReading*>(reading);
  ++r.entries;
  if (entry->maj_num == H5E_RESOURCE) r.resource = true;
  return 0;
}

/// The failure of the HDF5 call just made, read from HDF5's error stack before it is cleared.
[[noreturn]] void fail(const std::string& what) {
  StackReading r;
  const bool read = H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, read_entry, &r) >= 0;
  using Cause = Hdf5Failure::Cause;
  throw Hdf5Failure(what, r.resource ? Cause::resource : (!read || r.entries == 0) ? Cause::unrecorded : Cause::call);
}

/// An HDF5 identifier closed by its own close function.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) fail(what);
  }
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(Handle&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void check(herr_t status, const std::string& what) {
  if (status < 0) fail(what);
}

/// HDF5 prints its error stack on stderr by default; nhc reports failures in its own words.
void silence_hdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

Handle string_type(std::size_t length) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "make a string type");
  check(H5Tset_size(type, std::max<std::size_t>(1, length)), "size a string type");
  check(H5Tset_strpad(type, H5T_STR_NULLPAD), "pad a string type");
  return type;
}

Handle outcome_type() {
  Handle type(H5Tenum_create(H5T_NATIVE_INT8), H5Tclose, "make the outcome type");
  for (Outcome o : {Outcome::pending, Outcome::ok, Outcome::singular, Outcome::failed, Outcome::stopped}) {
    const auto v = static_cast<std::int8_t>(o);
    check(H5Tenum_insert(type, to_string(o), &v), "name an outcome");
  }
  return type;
}

// ---- writing ------------------------------------------------------------------------------

void attribute(hid_t object, const char* name, hid_t type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a scalar space");
  Handle a(H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
           std::string("create attribute ") + name);
  check(H5Awrite(a, type, value), std::string("write attribute ") + name);
}
void attribute(hid_t object, const char* name, double v) { attribute(object, name, H5T_NATIVE_DOUBLE, &v); }
void attribute(hid_t object, const char* name, long long v) { attribute(object, name, H5T_NATIVE_LLONG, &v); }
void attribute(hid_t object, const char* name, const std::string& v) {
  Handle type = string_type(v.size());
  std::string padded = v;
  padded.resize(std::max<std::size_t>(1, v.size()), '\0');
  attribute(object, name, type, padded.data());
}

void dataset(hid_t group, const char* name, hid_t type, const std::vector<hsize_t>& dims, const void* data) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, "make a space");
  Handle d(H5Dcreate2(group, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
           std::string("create dataset ") + name);
  hsize_t count = 1;
  for (hsize_t n : dims) count *= n;
  if (count > 0) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), std::string("write dataset ") + name);
}

void strings(hid_t group, const char* name, const std::vector<std::string>& values) {
  std::size_t length = 1;
  for (const std::string& s : values) length = std::max(length, s.size());
  std::vector<char> buffer(values.size() * length, '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    std::copy(values[k].begin(), values[k].end(), buffer.begin() + static_cast<long>(k * length));
  Handle type = string_type(length);
  dataset(group, name, type, {values.size()}, buffer.data());
}

Handle group(hid_t file, const char* name) {
  return Handle(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                std::string("create group ") + name);
}

void write_attributes(hid_t file, const EnsembleResults& results) {
  const EnsembleInfo& i = results.info;
  attribute(file, "format", std::string(kFormat));
  attribute(file, "scene", i.scene);
  attribute(file, "scene_file", i.scene_file);
  attribute(file, "scene_digest", i.scene_digest);
  attribute(file, "model", i.model);
  attribute(file, "nhc_version", i.nhc_version);
  attribute(file, "rtol", i.rtol);
  attribute(file, "atol", i.atol);
  attribute(file, "t0", i.t0);
  attribute(file, "t_end", i.t_end);
  attribute(file, "outputs", static_cast<long long>(i.outputs));
  attribute(file, "period", i.period);
  attribute(file, "keep", std::string(i.keep_trajectories ? "trajectories" : "final"));
  attribute(file, "design", std::string(i.design.kind == Design::Kind::grid ? "grid" : "sample"));
  attribute(file, "seed", static_cast<long long>(i.design.seed));
  attribute(file, "runs", static_cast<long long>(i.design.runs));
  attribute(file, "finished", static_cast<long long>(results.finished()));
  attribute(file, "ranks", static_cast<long long>(i.ranks));
  attribute(file, "threads", static_cast<long long>(i.threads));
  attribute(file, "wall_seconds", i.wall_seconds);
}

void write_design(hid_t file, const Design& d) {
  Handle g = group(file, "design");
  strings(g, "names", d.names());
  std::vector<std::string> specs;
  for (const VariableSpec& v : d.variables) specs.push_back(v.text);
  strings(g, "specs", specs);
  dataset(g, "values", H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(d.runs), d.variables.size()}, d.values.data());
  if (d.kind == Design::Kind::grid) {
    const std::vector<long long> shape(d.grid_shape.begin(), d.grid_shape.end());
    dataset(g, "grid_shape", H5T_NATIVE_LLONG, {shape.size()}, shape.data());
  }
}

/// One value of every record, gathered into a column.
template <class T, class F>
std::vector<T> column(const std::vector<RunRecord>& records, F f) {
  std::vector<T> out;
  out.reserve(records.size());
  for (const RunRecord& r : records) out.push_back(static_cast<T>(f(r)));
  return out;
}

/// A row-per-record matrix of `width` values (NaN where a record has none).
std::vector<double> matrix(const std::vector<RunRecord>& records, std::size_t width,
                           const std::function<const std::vector<double>&(const RunRecord&)>& f) {
  std::vector<double> out(records.size() * width, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < records.size(); ++k) {
    const std::vector<double>& v = f(records[k]);
    std::copy_n(v.begin(), std::min(width, v.size()), out.begin() + static_cast<long>(k * width));
  }
  return out;
}

void write_runs(hid_t file, const EnsembleResults& results) {
  const auto& rs = results.records;
  const auto runs = static_cast<hsize_t>(rs.size());
  const std::size_t n_states = results.info.state_names.size(), n_inv = results.info.invariant_names.size();
  Handle g = group(file, "runs");
  Handle otype = outcome_type();
  const auto outcome = column<std::int8_t>(rs, [](const RunRecord& r) { return static_cast<std::int8_t>(r.outcome); });
  dataset(g, "outcome", otype, {runs}, outcome.data());
  const auto t_stop = column<double>(rs, [](const RunRecord& r) { return r.t_stop; });
  dataset(g, "t_stop", H5T_NATIVE_DOUBLE, {runs}, t_stop.data());
  strings(g, "message", column<std::string>(rs, [](const RunRecord& r) { return r.message; }));
  strings(g, "events", column<std::string>(rs, [](const RunRecord& r) { return r.events; }));
  strings(g, "state_names", results.info.state_names);
  dataset(g, "final_state", H5T_NATIVE_DOUBLE, {runs, n_states},
          matrix(rs, n_states, [](const RunRecord& r) -> const std::vector<double>& { return r.final_state; }).data());
  strings(g, "invariant_names", results.info.invariant_names);
  dataset(g, "invariant_drift", H5T_NATIVE_DOUBLE, {runs, n_inv},
          matrix(rs, n_inv, [](const RunRecord& r) -> const std::vector<double>& { return r.invariant_drift; }).data());
  const auto hidden = column<double>(rs, [](const RunRecord& r) { return r.hidden_drift; });
  dataset(g, "hidden_drift", H5T_NATIVE_DOUBLE, {runs}, hidden.data());
  const auto steps = column<long long>(rs, [](const RunRecord& r) { return r.steps; });
  dataset(g, "steps", H5T_NATIVE_LLONG, {runs}, steps.data());
  const auto seconds = column<double>(rs, [](const RunRecord& r) { return r.seconds; });
  dataset(g, "seconds", H5T_NATIVE_DOUBLE, {runs}, seconds.data());
  const auto rank = column<int>(rs, [](const RunRecord& r) { return r.rank; });
  dataset(g, "rank", H5T_NATIVE_INT, {runs}, rank.data());
}

void write_trajectories(hid_t file, const EnsembleResults& results) {
  const EnsembleInfo& i = results.info;
  Handle g = group(file, "trajectories");
  RunSpec spec;
  spec.t0 = i.t0;
  spec.t_end = i.t_end;
  spec.outputs = i.outputs;
  spec.period = i.period;
  const std::vector<double> times = spec.times();
  dataset(g, "t", H5T_NATIVE_DOUBLE, {times.size()}, times.data());
  const std::size_t width = times.size() * i.state_names.size();
  dataset(g, "y", H5T_NATIVE_DOUBLE, {results.records.size(), times.size(), i.state_names.size()},
          matrix(results.records, width, [](const RunRecord& r) -> const std::vector<double>& {
            return r.trajectory;
          }).data());
}

// ---- reading ------------------------------------------------------------------------------

struct Reader {
  std::string path;
  hid_t file;

  [[noreturn]] void bad(const std::string& why) const {
    throw InputError({path, 0, 0}, "not an nhc ensemble file: " + why);
  }

  Handle open_attribute(const char* name) const {
    if (H5Aexists(file, name) <= 0) bad(std::string("attribute ") + name + " is missing");
    return Handle(H5Aopen(file, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
  }
  double number(const char* name) const {
    Handle a = open_attribute(name);
    double v = 0;
    check(H5Aread(a, H5T_NATIVE_DOUBLE, &v), std::string("read attribute ") + name);
    return v;
  }
  long long integer(const char* name) const {
    Handle a = open_attribute(name);
    long long v = 0;
    check(H5Aread(a, H5T_NATIVE_LLONG, &v), std::string("read attribute ") + name);
    return v;
  }
  /// The number of an attribute that older files lack: 0 when absent.
  double optional_number(const char* name) const { return H5Aexists(file, name) > 0 ? number(name) : 0.0; }
  /// The text of an attribute that older files lack: "" when absent.
  std::string optional_text(const char* name) const { return H5Aexists(file, name) > 0 ? text(name) : std::string(); }

  std::string text(const char* name) const {
    Handle a = open_attribute(name);
    Handle type(H5Aget_type(a), H5Tclose, "read a type");
    if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0) bad(std::string(name) + " is not a string");
    std::string v(H5Tget_size(type), '\0');
    check(H5Aread(a, type, v.data()), std::string("read attribute ") + name);
    return v.substr(0, v.find('\0'));
  }

  Handle open_dataset(const std::string& name) const {
    if (H5Lexists(file, name.substr(0, name.find('/', 1)).c_str(), H5P_DEFAULT) <= 0 ||
        H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
      bad("dataset " + name + " is missing");
    return Handle(H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  }
  std::vector<hsize_t> dims(hid_t d) const {
    Handle space(H5Dget_space(d), H5Sclose, "read a space");
    std::vector<hsize_t> out(static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(space))));
    H5Sget_simple_extent_dims(space, out.data(), nullptr);
    return out;
  }
  template <class T>
  std::vector<T> numbers(const std::string& name, hid_t type, const std::vector<hsize_t>& expected) const {
    Handle d = open_dataset(name);
    if (dims(d) != expected) bad("dataset " + name + " has the wrong shape");
    hsize_t count = 1;
    for (hsize_t n : expected) count *= n;
    std::vector<T> out(count);
    if (count > 0) check(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "read dataset " + name);
    return out;
  }
  std::vector<std::string> strings(const std::string& name) const {
    Handle d = open_dataset(name);
    const std::vector<hsize_t> n = dims(d);
    if (n.size() != 1) bad("dataset " + name + " has the wrong shape");
    Handle type(H5Dget_type(d), H5Tclose, "read a type");
    if (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) > 0) bad(name + " is not a string array");
    const std::size_t length = H5Tget_size(type);
    std::vector<char> buffer(n[0] * length);
    if (n[0] > 0) check(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()), "read dataset " + name);
    std::vector<std::string> out;
    for (hsize_t k = 0; k < n[0]; ++k) {
      std::string s(buffer.data() + k * length, length);
      out.push_back(s.substr(0, s.find('\0')));
    }
    return out;
  }
};

EnsembleInfo read_info(const Reader& in) {
  if (in.text("format") != kFormat) in.bad("format is '" + in.text("format") + "', expected '" + kFormat + "'");
  EnsembleInfo i;
  i.scene = in.text("scene");
  i.scene_file = in.text("scene_file");
  i.scene_digest = in.optional_text("scene_digest");
  i.model = in.text("model");
  i.nhc_version = in.text("nhc_version");
  i.rtol = in.number("rtol");
  i.atol = in.number("atol");
  i.t0 = in.number("t0");
  i.t_end = in.number("t_end");
  i.outputs = static_cast<int>(in.integer("outputs"));
  i.period = in.optional_number("period");
  i.keep_trajectories = in.text("keep") == "trajectories";
  i.ranks = static_cast<int>(in.integer("ranks"));
  i.threads = static_cast<int>(in.integer("threads"));
  i.wall_seconds = in.number("wall_seconds");
  Design& d = i.design;
  d.kind = in.text("design") == "grid" ? Design::Kind::grid : Design::Kind::sample;
  d.seed = static_cast<std::uint64_t>(in.integer("seed"));
  d.runs = static_cast<long>(in.integer("runs"));
  const std::vector<std::string> names = in.strings("/design/names"), specs = in.strings("/design/specs");
  if (specs.size() != names.size()) in.bad("/design/specs and /design/names differ in length");
  for (std::size_t k = 0; k < names.size(); ++k) {
    VariableSpec v;
    v.name = names[k];
    v.text = specs[k];
    d.variables.push_back(v);
  }
  d.values = in.numbers<double>("/design/values", H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(d.runs), names.size()});
  if (d.kind == Design::Kind::grid) {
    const auto shape = in.numbers<long long>("/design/grid_shape", H5T_NATIVE_LLONG, {names.size()});
    d.grid_shape.assign(shape.begin(), shape.end());
    for (std::size_t k = 0; k < names.size(); ++k) d.variables[k].n = static_cast<long>(shape[k]);
  }
  i.state_names = in.strings("/runs/state_names");
  i.invariant_names = in.strings("/runs/invariant_names");
  return i;
}

std::vector<RunRecord> read_runs(const Reader& in, const EnsembleInfo& i) {
  const auto runs = static_cast<hsize_t>(i.design.runs);
  const std::size_t ns = i.state_names.size(), ni = i.invariant_names.size();
  const auto outcome = in.numbers<std::int8_t>("/runs/outcome", H5T_NATIVE_INT8, {runs});
  const auto t_stop = in.numbers<double>("/runs/t_stop", H5T_NATIVE_DOUBLE, {runs});
  const auto message = in.strings("/runs/message");
  // Older files have no events column: no event was located then.
  const auto events =
      H5Lexists(in.file, "/runs/events", H5P_DEFAULT) > 0 ? in.strings("/runs/events") : std::vector<std::string>(runs);
  const auto final_state = in.numbers<double>("/runs/final_state", H5T_NATIVE_DOUBLE, {runs, ns});
  const auto drift = in.numbers<double>("/runs/invariant_drift", H5T_NATIVE_DOUBLE, {runs, ni});
  const auto hidden = in.numbers<double>("/runs/hidden_drift", H5T_NATIVE_DOUBLE, {runs});
  const auto steps = in.numbers<long long>("/runs/steps", H5T_NATIVE_LLONG, {runs});
  const auto seconds = in.numbers<double>("/runs/seconds", H5T_NATIVE_DOUBLE, {runs});
  const auto rank = in.numbers<int>("/runs/rank", H5T_NATIVE_INT, {runs});
  if (message.size() != runs) in.bad("/runs/message has the wrong length");
  if (events.size() != runs) in.bad("/runs/events has the wrong length");
  std::vector<double> trajectories;
  const std::size_t width = (static_cast<std::size_t>(i.outputs) + 1) * ns;
  if (i.keep_trajectories)
    trajectories =
        in.numbers<double>("/trajectories/y", H5T_NATIVE_DOUBLE, {runs, static_cast<hsize_t>(i.outputs) + 1, ns});
  std::vector<RunRecord> records(runs);
  for (std::size_t k = 0; k < runs; ++k) {
    RunRecord& r = records[k];
    r.index = static_cast<std::int64_t>(k);
    if (outcome[k] < 0 || outcome[k] > static_cast<std::int8_t>(Outcome::stopped)) in.bad("an outcome is out of range");
    r.outcome = static_cast<Outcome>(outcome[k]);
    r.t_stop = t_stop[k];
    r.message = message[k];
    r.events = events[k];
    r.final_state.assign(final_state.begin() + static_cast<long>(k * ns),
                         final_state.begin() + static_cast<long>((k + 1) * ns));
    r.invariant_drift.assign(drift.begin() + static_cast<long>(k * ni),
                             drift.begin() + static_cast<long>((k + 1) * ni));
    r.hidden_drift = hidden[k];
    r.steps = steps[k];
    r.seconds = seconds[k];
    r.rank = rank[k];
    if (i.keep_trajectories)
      r.trajectory.assign(trajectories.begin() + static_cast<long>(k * width),
                          trajectories.begin() + static_cast<long>((k + 1) * width));
  }
  return records;
}

}  // namespace

void check_writable(const std::string& path) { check_can_create(path); }

/// The file is made in memory (HDF5's core driver, no backing store) and written by the one
/// atomic writer of nhc: HDF5 never meets a full disk, whose failed flush would leave it a file
/// it cannot close (it crashed at exit), and disk-full or permission failures read as every
/// other output's do (exit 4 with the system's reason).
void write_results(const std::string& path, const EnsembleResults& results) {
  silence_hdf5();
  std::vector<char> image;
  // A failure here is nhc's own (a wrong call: it propagates as such) unless HDF5 ran out of
  // memory for the file it keeps there: then the machine cannot hold the results (exit 4).
  try {
    Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "make file access properties");
    check(H5Pset_fapl_core(access, 1 << 16, false), "keep the file in memory");
    Handle file(H5Fcreate("nhc-ensemble-in-memory.h5", H5F_ACC_TRUNC, H5P_DEFAULT, access), H5Fclose,
                "create the file in memory");
    write_attributes(file, results);
    write_design(file, results.info.design);
    write_runs(file, results);
    if (results.info.keep_trajectories) write_trajectories(file, results);
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush the file in memory");
    const ssize_t size = H5Fget_file_image(file, nullptr, 0);
    if (size < 0) fail("measure the file's image");
    image.resize(static_cast<std::size_t>(size));
    if (H5Fget_file_image(file, image.data(), image.size()) != size) fail("copy the file's image");
  } catch (const Hdf5Failure& e) {
    if (e.cause() == Hdf5Failure::Cause::call) throw;  // nhc's bug: "internal error"
    throw EnvironmentError(
        "cannot write " + path + ": " + e.what() + " in memory: " +
        (e.cause() == Hdf5Failure::Cause::resource ? std::strerror(ENOMEM) : "HDF5 gave no reason (out of memory?)"));
  }
  write_file_atomically(
      path, [&](std::ostream& out) { out.write(image.data(), static_cast<std::streamsize>(image.size())); });
}

EnsembleResults read_results(const std::string& path) {
  silence_hdf5();
  // No size limit: an ensemble's trajectories may take gigabytes, and HDF5 reads only what is asked.
  check_input_file(path, "an HDF5 file", std::numeric_limits<std::uintmax_t>::max());
  if (FILE* probe = std::fopen(path.c_str(), "rb")) std::fclose(probe);
  else throw InputError({path, 0, 0}, std::string("cannot read: ") + std::strerror(errno));
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError({path, 0, 0}, "not an HDF5 file (or it cannot be read)");
  // A file that starts as HDF5 but is truncated or damaged fails to open or to read: bad input.
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0)
    throw InputError({path, 0, 0},
                     "the HDF5 file is damaged or truncated: it cannot be opened "
                     "(was it written completely by nhc ensemble?)");
  Handle file(id, H5Fclose, "open " + path);
  const Reader in{path, file};
  try {
    EnsembleResults results;
    results.info = read_info(in);
    results.records = read_runs(in, results.info);
    return results;
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError({path, 0, 0}, std::string("the HDF5 file is damaged or not an ensemble of nhc: ") + e.what());
  }
}

std::string resume_mismatch(const EnsembleInfo& s, const EnsembleInfo& w) {
  auto differ = [](const std::string& what, const std::string& a, const std::string& b) {
    return what + " is " + a + " there, " + b + " now";
  };
  if (s.scene != w.scene) return differ("the scene", s.scene, w.scene);
  // By content: a scene edited under the same name is another system.
  if (s.scene_digest.empty()) return "it records no digest of its scene's text (written by an older nhc)";
  if (s.scene_digest != w.scene_digest)
    return "the scene's text or its --initial values differ from those its runs were computed from (SHA-256 " +
           s.scene_digest.substr(0, 12) + "… there, " + w.scene_digest.substr(0, 12) + "… now)";
  if (s.model != w.model) return differ("the model", s.model, w.model);
  if (s.rtol != w.rtol || s.atol != w.atol) return "the tolerances differ";
  if (s.t0 != w.t0 || s.t_end != w.t_end || s.outputs != w.outputs || s.period != w.period)
    return "t0, t_end, --outputs or the controller's period differ";
  if (s.keep_trajectories != w.keep_trajectories) return "--keep differs";
  if (s.state_names != w.state_names || s.invariant_names != w.invariant_names) return "the model's states differ";
  const Design &a = s.design, &b = w.design;
  if (a.kind != b.kind || a.names() != b.names() || a.runs != b.runs || a.grid_shape != b.grid_shape ||
      a.seed != b.seed || a.values != b.values)
    return "the design (--vary/--sample, --samples, --seed) differs";
  return "";
}

}  // namespace nhc::ensemble
