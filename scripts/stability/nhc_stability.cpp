// nhc_stability MANIFEST [-o FILE.md | --check FILE.md] [--quiet]
//
// A repository maintenance tool, not part of the nhc command: runs the cases of a manifest
// (docs/stability.toml), the stiff and extreme scenes of examples/ with their documented
// expectations. Each case is a work-precision measurement (nhc/runtime/work_precision.hpp) with
// the expected outcome, either an accuracy met (with optional bounds on steps and drift) or a
// diagnostic stop at a given t. It writes the table of docs/stability.md, or with --check
// compares it with the file (wall times excluded: they differ from run to run) and fails when it
// is stale. Either way the exit code is 3 when a case misses its expectation.
// CMake: target `stability` regenerates docs/stability.md; test `report:stability_current`.
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/base/clock.hpp"
#include "nhc/base/number_text.hpp"
#include "work_precision.hpp"

namespace {

namespace fs = std::filesystem;
using namespace nhc;
using namespace nhc::cli;

struct Options {
  std::string manifest, output, check;
  bool quiet = false;
};

constexpr int kOk = 0, kInternal = 1, kBadInput = 2, kMissed = 3;

std::string fmt(double v, int precision = 3) {
  return std::isnan(v) ? std::string("—") : base::number_text(v, precision);
}

std::string table_row(const std::vector<std::string>& cells) {
  std::string row = "|";
  for (const std::string& c : cells) row += " " + c + " |";
  return row + "\n";
}

ProgressSink progress_sink(bool quiet) {
  if (quiet) return {};
  const auto start = base::Clock::now();
  return [start](const std::string& line) {
    if (base::seconds_since(start) > 1.0) std::cerr << "nhc_stability: " << line << std::endl;
  };
}

/// rtol values by decades, "HI:LO" or one value; the case names the flag-like key in errors.
std::vector<double> decades_of(const std::string& manifest, const std::string& key, const std::string& spec) {
  try {
    return decades(key, spec);
  } catch (const std::invalid_argument& e) {
    throw InputError({manifest, 0, 0}, e.what());
  }
}

struct StabilityCase {
  std::string id, title, scene, model, tolerances, projection = "off", sweep, expect, diagnostic, advice;
  std::optional<double> t_end, accuracy, max_steps, max_hidden_drift, max_invariant_drift, t_stop, atol_scale;
  std::vector<std::string> set;
};

std::vector<StabilityCase> load_manifest(const std::string& path) {
  toml::table doc;
  try {
    doc = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError({path, static_cast<int>(b.line), static_cast<int>(b.column)}, std::string(e.description()));
  }
  std::vector<StabilityCase> cases;
  const toml::array* array = doc["case"].as_array();
  if (!array) throw InputError({path, 1, 1}, "expected [[case]] tables");
  for (const toml::node& node : *array) {
    const toml::table* t = node.as_table();
    const int line = static_cast<int>(node.source().begin.line);
    if (!t) throw InputError({path, line, 1}, "[[case]] must be a table");
    auto text = [&](const char* key, bool required) {
      const auto v = (*t)[key].value<std::string>();
      if (!v && required) throw InputError({path, line, 1}, std::string("case without '") + key + "'");
      return v.value_or("");
    };
    auto number = [&](const char* key) -> std::optional<double> {
      if (!t->contains(key)) return std::nullopt;
      const auto v = (*t)[key].value<double>();
      if (!v) throw InputError({path, line, 1}, std::string("'") + key + "' must be a number");
      return v;
    };
    StabilityCase c;
    c.id = text("id", true);
    c.title = text("title", true);
    c.scene = text("scene", true);
    c.model = text("model", false);
    c.tolerances = text("tolerances", false);
    if (t->contains("projection")) c.projection = text("projection", true);
    c.sweep = text("sweep", false);
    c.expect = text("expect", true);
    c.diagnostic = text("diagnostic", false);
    c.advice = text("advice", true);
    c.t_end = number("t_end");
    c.accuracy = number("accuracy");
    c.max_steps = number("max_steps");
    c.max_hidden_drift = number("max_hidden_drift");
    c.max_invariant_drift = number("max_invariant_drift");
    c.t_stop = number("t_stop");
    c.atol_scale = number("atol_scale");
    if (const toml::array* set = (*t)["set"].as_array())
      for (const toml::node& s : *set)
        if (auto v = s.value<std::string>()) c.set.push_back(*v);
    if (c.expect != "accuracy" && c.expect != "diagnostic")
      throw InputError({path, line, 1}, "case " + c.id + ": expect must be \"accuracy\" or \"diagnostic\"");
    if (c.expect == "accuracy" && !c.accuracy) throw InputError({path, line, 1}, "case " + c.id + ": no accuracy");
    if (c.expect == "diagnostic" && (c.diagnostic.empty() || !c.t_stop))
      throw InputError({path, line, 1}, "case " + c.id + ": a diagnostic case needs diagnostic and t_stop");
    if (c.projection != "off" && c.projection != "on" && c.projection != "both")
      throw InputError({path, line, 1}, "case " + c.id + ": projection must be off, on or both");
    cases.push_back(std::move(c));
  }
  return cases;
}

/// Whether a measurement meets its case's expectation; `why` says what it missed.
bool meets(const StabilityCase& c, const Measurement& m, std::string& why) {
  std::ostringstream w;
  if (c.expect == "accuracy") {
    if (m.failure) w << "stopped: " << m.failure_message << "; ";
    if (!(m.error <= *c.accuracy)) w << "error " << fmt(m.error) << " > " << fmt(*c.accuracy) << "; ";
  } else {
    if (!m.failure) w << "ran through, expected " << c.diagnostic << "; ";
    else if (m.status() != c.diagnostic) w << "stopped with " << m.status() << ", expected " << c.diagnostic << "; ";
    else if (!(std::abs(m.failure_t - *c.t_stop) <= 1e-6 * std::abs(*c.t_stop) + 1e-15))
      w << "stopped at t = " << fmt(m.failure_t, 10) << ", expected " << fmt(*c.t_stop, 10) << "; ";
    if (c.accuracy && !(m.error <= *c.accuracy)) w << "error " << fmt(m.error) << " > " << fmt(*c.accuracy) << "; ";
  }
  if (c.max_steps && m.statistics.steps > *c.max_steps)
    w << m.statistics.steps << " steps > " << fmt(*c.max_steps) << "; ";
  if (c.max_hidden_drift && !(m.max_hidden <= *c.max_hidden_drift))
    w << "hidden drift " << fmt(m.max_hidden) << " > " << fmt(*c.max_hidden_drift) << "; ";
  if (c.max_invariant_drift && !(m.max_invariant_relative <= *c.max_invariant_drift))
    w << "invariant drift " << fmt(m.max_invariant_relative) << " > " << fmt(*c.max_invariant_drift) << "; ";
  why = w.str();
  return why.empty();
}

std::string expectation(const StabilityCase& c) {
  std::ostringstream e;
  if (c.expect == "accuracy") e << "error ≤ " << fmt(*c.accuracy);
  else {
    std::string d = c.diagnostic;
    std::replace(d.begin(), d.end(), '_', ' ');
    e << d << " at t = " << fmt(*c.t_stop, 6);
    if (c.accuracy) e << ", error ≤ " << fmt(*c.accuracy);
  }
  if (c.max_steps) e << ", steps ≤ " << fmt(*c.max_steps);
  if (c.max_hidden_drift) e << ", hidden drift ≤ " << fmt(*c.max_hidden_drift);
  if (c.max_invariant_drift) e << ", invariant drift ≤ " << fmt(*c.max_invariant_drift);
  return e.str();
}

std::string outcome(const Measurement& m) {
  if (!m.failure) return "ran to t_end";
  std::string d = m.status();
  std::replace(d.begin(), d.end(), '_', ' ');
  return "stopped: " + d + " at t = " + fmt(m.failure_t, 6);
}

/// The measurement settings of a case: dense LU, one repeat, the case's tolerances (default: the
/// scene's [simulate] rtol), atol scale, t_end, parameters and sweep.
WorkPrecisionSettings settings_of(const std::string& manifest, const StabilityCase& c, const Scene& scene) {
  WorkPrecisionSettings s;
  s.rtols = c.tolerances.empty() ? std::vector<double>{scene.simulate.rtol}
                                 : decades_of(manifest, "tolerances", c.tolerances);
  s.atol_scale = c.atol_scale.value_or(scene.simulate.atol / scene.simulate.rtol);
  s.t_end = c.t_end.value_or(scene.simulate.t_end);
  s.max_repeats = 1;
  for (bool projection : {false, true})
    if (c.projection == "both" || (c.projection == "on") == projection)
      s.configurations.push_back({"dense", projection});
  for (const std::string& a : c.set) {
    const size_t eq = a.find('=');
    if (eq == std::string::npos)
      throw InputError({manifest, 0, 0}, "case " + c.id + ": set " + a + ": expected NAME=VALUE");
    s.parameter_overrides.emplace_back(a.substr(0, eq), std::stod(a.substr(eq + 1)));
  }
  if (!c.sweep.empty()) {
    const size_t eq = c.sweep.find('='), colon = c.sweep.find(':');
    if (eq == std::string::npos || colon == std::string::npos)
      throw InputError({manifest, 0, 0}, "case " + c.id + ": sweep " + c.sweep + ": expected NAME=LO:HI");
    s.sweep_parameter = c.sweep.substr(0, eq);
    double lo = std::stod(c.sweep.substr(eq + 1, colon - eq - 1)), hi = std::stod(c.sweep.substr(colon + 1));
    if (lo > hi) std::swap(lo, hi);
    s.sweep_values = decades_of(manifest, "sweep", base::number_text(hi, 17) + ":" + base::number_text(lo, 17));
    std::reverse(s.sweep_values.begin(), s.sweep_values.end());  // increasing
  }
  return s;
}

/// Table rows: the last cell (seconds) is left out of the staleness comparison.
std::string without_timing(const std::string& doc) {
  std::istringstream in(doc);
  std::ostringstream out;
  for (std::string line; std::getline(in, line);) {
    if (line.size() > 2 && line[0] == '|' && line.back() == '|') {
      const size_t last = line.rfind('|', line.size() - 2);
      line = line.substr(0, last + 1) + " |";
    }
    out << line << "\n";
  }
  return out.str();
}

int run_stability(const Options& o) {
  const std::vector<StabilityCase> cases = load_manifest(o.manifest);
  const fs::path root = fs::path(o.manifest).parent_path().parent_path();  // docs/stability.toml → the project
  const ProgressSink progress = progress_sink(o.quiet);

  std::ostringstream table, advice;
  int missed = 0;
  table << table_row({"case", "configuration", "rtol", "error against", "error", "steps", "hidden drift",
                      "invariant drift", "outcome", "expected", "met", "seconds"});
  table << table_row(std::vector<std::string>(12, "---"));
  for (const StabilityCase& c : cases) {
    if (!o.quiet) std::cerr << "nhc_stability: " << c.id << " (" << c.scene << ")" << std::endl;
    const Scene scene = load_scene((root / c.scene).string());
    const ModelKind kind = model_or_default(scene, c.model);
    const WorkPrecision wp = measure_work_precision(scene, kind, settings_of(o.manifest, c, scene), progress);
    for (const Measurement& m : wp.measurements) {
      std::string why;
      const bool ok = meets(c, m, why);
      if (!ok) {
        ++missed;
        std::cerr << "nhc_stability: case " << c.id << " (" << m.configuration.label() << ", rtol " << fmt(m.rtol)
                  << ") missed its expectation: " << why << "\n";
      }
      std::string config = m.configuration.label();
      if (m.sweep_value) config += ", " + wp.settings.sweep_parameter + " = " + fmt(*m.sweep_value, 2);
      table << table_row({c.id, config, fmt(m.rtol, 2), wp.source.exact ? "reference" : "reference run",
                          fmt(m.error, 2), std::to_string(m.statistics.steps), wp.n_hidden ? fmt(m.max_hidden, 2) : "—",
                          wp.n_invariants ? fmt(m.max_invariant_relative, 2) : "—", outcome(m), expectation(c),
                          ok ? "yes" : "**no**", fmt(m.seconds, 2)});
    }
    advice << "### " << c.id << ": " << c.title << "\n\n"
           << "Scene `" << c.scene << "`, model " << wp.model_name << ", t_end " << fmt(wp.settings.t_end, 6)
           << ", atol = rtol × " << fmt(wp.settings.atol_scale);
    for (const std::string& s : c.set) advice << ", " << s;
    if (!c.sweep.empty()) advice << ", sweep " << c.sweep << " (by decades)";
    advice << ". Error against " << wp.source.description() << ".\n\n" << c.advice << "\n\n";
  }

  std::ostringstream doc;
  doc << "# Stability: stiff and extreme scenes\n\n"
      << "<!-- Generated by the maintenance tool scripts/stability/ (CMake target `stability`); do not\n"
      << "     edit: change docs/stability.toml and regenerate. The test\n"
      << "     `report:stability_current` fails when the table is stale (every column but seconds). -->\n\n"
      << "Each case is one scene of `examples/` measured as `nhc report` does (dense LU, generated Jacobian;\n"
      << "atol = rtol × the scene's [simulate] atol/rtol unless stated) with its documented expectation: an\n"
      << "accuracy to meet, or a diagnostic to stop with at a given t. error = max over 201 output times and the\n"
      << "coordinates of |q − q_ref|, against the scene's [reference] where it has one, else against a reference\n"
      << "run at rtol 1e-13. hidden drift = max |g_i| of the hidden constraints; invariant drift = max\n"
      << "|I(t) − I(t0)| / max |I(t)| over the scene's invariants (absolute when max |I(t)| < 1e-8,\n"
      << "runtime::kInvariantScaleFloor); \"+ projection\" = projection onto the hidden\n"
      << "constraints (docs/projection.md). seconds = wall time of one run on the machine that generated\n"
      << "this file (not compared by the staleness test). The work-precision plot of each case:\n"
      << "`nhc report <scene>` (README).\n\n"
      << table.str() << "\n"
      << "## What to do in each case\n\n"
      << advice.str();
  const std::string text = doc.str();

  if (!o.check.empty()) {
    std::ifstream in(o.check);
    std::stringstream current;
    current << in.rdbuf();
    if (!in || without_timing(current.str()) != without_timing(text)) {
      const std::string fresh = o.check + ".new";
      write_file_atomically(fresh, [&](std::ostream& out) { out << text; });
      std::cerr << "nhc_stability: " << o.check << " is stale; the current table is in " << fresh
                << " (regenerate with the CMake target `stability`)\n";
      return kInternal;
    }
    if (!o.quiet) std::cout << "nhc_stability: " << o.check << " is current\n";
  } else if (o.output.empty()) {
    std::cout << text;
  } else {
    write_file_atomically(o.output, [&](std::ostream& out) { out << text; });
    if (!o.quiet) std::cout << "nhc_stability: wrote " << o.output << "\n";
  }
  if (missed > 0) {
    std::cerr << "nhc_stability: error: " << missed << " run(s) of the stability cases missed their expectation\n";
    return kMissed;
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "-o" || a == "--output" || a == "--check") && i + 1 < argc)
      (a == "--check" ? o.check : o.output) = argv[++i];
    else if (a == "-q" || a == "--quiet") o.quiet = true;
    else if (!a.empty() && a[0] != '-' && o.manifest.empty()) o.manifest = a;
    else {
      std::cerr << "usage: nhc_stability MANIFEST [-o FILE.md | --check FILE.md] [--quiet]\n";
      return kBadInput;
    }
  }
  if (o.manifest.empty()) {
    std::cerr << "usage: nhc_stability MANIFEST [-o FILE.md | --check FILE.md] [--quiet]\n";
    return kBadInput;
  }
  try {
    return run_stability(o);
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return kBadInput;
  } catch (const MathError& e) {
    std::cerr << "nhc_stability: error: " << e.what() << "\n";
    return kMissed;
  } catch (const std::exception& e) {
    std::cerr << "nhc_stability: internal error: " << e.what() << "\n";
    return kInternal;
  }
}
