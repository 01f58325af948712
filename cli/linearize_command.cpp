// nhc linearize SCENE [--model M] [--at NAME=VALUE]... [--keep NAME,...] [--states NAME,...] [--turn A:X,Y] [--sweep
// NAME=a:b:n] [--format text|json] [-o DIR]
//
// Linear stability of an equilibrium or steady motion (docs/linearize.md, nhc::linearize):
// the operating point, cyclic coordinates removed, the matrix A on the constraint manifold in a
// minimal set of states, its eigenvalues and a verdict; with --sweep the eigenvalues along a
// parameter or initial value, the values where the verdict changes (bisection to 1e-10
// relative) and DIR/stability.csv, DIR/stability.svg/.png (gnuplot). JSON on stdout with
// --format json, and DIR/linearize.json with -o DIR. DIR is written as a whole: a temporary
// sibling directory renamed into place.
#include <unistd.h>

#include <complex>
#include <iomanip>
#include <limits>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "nhc/app/model_requirements.hpp"
#include "flag_rules.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/emit/json_writer.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/tools/gnuplot.hpp"
#include "nhc/linearize.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

namespace {

namespace fs = std::filesystem;

struct LinearizeFlags {
  std::string scene_path;
  std::string model;
  std::vector<std::string> at;
  std::vector<std::string> keep, states;
  std::string turn;
  std::string sweep;
  std::string format = "text";
  std::string output;
};

std::string full(double v) { return base::number_text(v, 10); }

void write_eigenvalues(JsonWriter& json, const std::vector<std::complex<double>>& eigenvalues) {
  json.begin_array();
  for (const auto& l : eigenvalues)
    json.begin_object().key("re").value(l.real()).key("im").value(l.imag()).end_object();
  json.end_array();
}

/// A matrix as an array of rows.
void write_matrix(JsonWriter& json, const Eigen::MatrixXd& m) {
  json.begin_array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    json.begin_array();
    for (Eigen::Index c = 0; c < m.cols(); ++c) json.value(m(r, c));
    json.end_array();
  }
  json.end_array();
}

/// A matrix with named rows and columns as CSV: a header row of the column names, then one row
/// per row name, led by it ("state,x,y'" then "x,0.5,1").
void write_matrix_csv(const fs::path& path, const Eigen::MatrixXd& m, const std::vector<std::string>& rows,
                      const std::vector<std::string>& columns) {
  write_file_atomically(path.string(), [&](std::ostream& out) {
    out << "state";
    for (const std::string& c : columns) out << "," << c;
    out << "\n";
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
      out << rows[static_cast<std::size_t>(r)];
      for (Eigen::Index c = 0; c < m.cols(); ++c) out << "," << base::shortest_text(m(r, c));
      out << "\n";
    }
  });
}

void write_json(std::ostream& out, const Linearization& lin, const std::optional<SweepResult>& sweep) {
  JsonWriter json(out);
  json.begin_object();
  json.key("scene").value(lin.scene).key("model").value(to_string(lin.model));
  json.key("point").begin_object();
  for (const auto& [name, value] : lin.point) json.key(name).value(value);
  json.end_object();
  json.key("cyclic").begin_array();
  for (const std::string& c : lin.cyclic) json.value(c);
  json.end_array();
  json.key("kept").begin_array();
  for (const std::string& c : lin.kept) json.value(c);
  json.end_array();
  json.key("turn_rate").value(lin.turn_rate);
  json.key("states").begin_array();
  for (const std::string& s : lin.states) json.value(s);
  json.end_array();
  json.key("eliminated").begin_array();
  for (const std::string& s : lin.eliminated) json.value(s);
  json.end_array();
  json.key("algebraic").begin_array();
  for (const std::string& s : lin.algebraic) json.value(s);
  json.end_array();
  json.key("basis").value(lin.basis);
  json.key("A");
  write_matrix(json, lin.A);
  json.key("inputs").begin_array();
  for (const std::string& u : lin.inputs) json.value(u);
  json.end_array();
  json.key("B");
  write_matrix(json, lin.B);
  json.key("outputs").begin_array();
  for (const std::string& h : lin.outputs) json.value(h);
  json.end_array();
  json.key("C");
  write_matrix(json, lin.C);
  json.key("D");
  write_matrix(json, lin.D);
  json.key("eigenvalues");
  write_eigenvalues(json, lin.eigenvalues);
  json.key("zero_eigenvalues").value(lin.zero_eigenvalues);
  json.key("families").begin_array();
  for (const SteadyFamily& f : lin.families) json.value(f.description);
  json.end_array();
  json.key("verdict").value(to_string(lin.verdict));
  json.key("defect").value(lin.defect);
  json.key("worst_state").value(lin.worst_state);
  if (sweep) {
    json.key("sweep").begin_array();
    for (const SweepPoint& p : sweep->points) {
      json.begin_object().key("value").value(p.value).key("eigenvalues");
      write_eigenvalues(json, p.linearization.eigenvalues);
      json.key("verdict").value(to_string(p.linearization.verdict)).end_object();
    }
    json.end_array();
    json.key("thresholds").begin_array();
    for (const VerdictChange& t : sweep->thresholds)
      json.begin_object()
          .key("value")
          .value(t.value)
          .key("from")
          .value(to_string(t.from))
          .key("to")
          .value(to_string(t.to))
          .end_object();
    json.end_array();
  }
  json.end_object();
  out << "\n";
}

void write_text(std::ostream& out, const Linearization& lin, const std::optional<SweepResult>& sweep) {
  out << "nhc linearize: " << lin.scene << ", model " << to_string(lin.model) << "\n";
  out << "  operating point:";
  for (const auto& [name, value] : lin.point) out << " " << name << " = " << full(value) << ";";
  out << "\n  defect " << base::number_text(lin.defect, 3) << " (largest |d/dt state| relative to 1 + max |state|, at "
      << (lin.worst_state.empty() ? "-" : lin.worst_state) << ")\n";
  out << "  cyclic coordinates removed: " << (lin.cyclic.empty() ? "none" : join_names(lin.cyclic)) << "\n";
  if (!lin.kept.empty()) out << "  cyclic coordinates kept as states: " << join_names(lin.kept) << "\n";
  if (lin.turn_rate != 0.0) out << "  relative equilibrium: the frame turns at " << full(lin.turn_rate) << " rad/s\n";
  out << "  reduced states (" << lin.states.size() << "): " << (lin.states.empty() ? "none" : join_names(lin.states))
      << "\n  basis: " << lin.basis << "\n";
  // A matrix under a header row of its column names, each row led by its name.
  const auto print = [&](const std::string& title, const Eigen::MatrixXd& m, const std::vector<std::string>& rows,
                         const std::vector<std::string>& columns) {
    out << "  " << title << " =\n";
    std::size_t label = 0;
    for (const std::string& r : rows) label = std::max(label, r.size());
    out << "    " << std::string(label, ' ');
    for (const std::string& c : columns) out << " " << std::setw(16) << c;
    out << "\n";
    for (Eigen::Index r = 0; r < m.rows(); ++r) {
      out << "    " << std::left << std::setw(static_cast<int>(label)) << rows[static_cast<std::size_t>(r)]
          << std::right;
      for (Eigen::Index c = 0; c < m.cols(); ++c) out << " " << std::setw(16) << full(m(r, c));
      out << "\n";
    }
  };
  print("A (row s: d(δs)/dt; column: δ of the state)", lin.A, lin.states, lin.states);
  if (!lin.inputs.empty()) {
    out << "  inputs (" << lin.inputs.size() << "): " << join_names(lin.inputs) << "\n";
    print("B (row s: d(δs)/dt; column: δ of the input)", lin.B, lin.states, lin.inputs);
  }
  if (!lin.outputs.empty()) {
    out << "  outputs (" << lin.outputs.size() << "): " << join_names(lin.outputs) << "\n";
    print("C (row: δ of the output; column: δ of the state)", lin.C, lin.outputs, lin.states);
    if (!lin.inputs.empty()) print("D (row: δ of the output; column: δ of the input)", lin.D, lin.outputs, lin.inputs);
  }
  out << "  eigenvalues:\n";
  for (const auto& l : lin.eigenvalues)
    out << "    " << full(l.real()) << (l.imag() < 0 ? " - " : " + ") << full(std::abs(l.imag())) << "i\n";
  out << "  zero eigenvalues: " << lin.zero_eigenvalues << ", of which " << lin.families.size()
      << " from families of steady motions\n";
  for (const SteadyFamily& f : lin.families) out << "    " << f.description << "\n";
  out << "  verdict: " << to_string(lin.verdict) << "\n";
  for (const std::string& note : lin.notes) out << "  note: " << note << "\n";
  if (!sweep) return;
  out << "  sweep of " << sweep->range.name << " from " << full(sweep->range.first) << " to " << full(sweep->range.last)
      << " (" << sweep->range.count << " values):\n";
  for (const SweepPoint& p : sweep->points) {
    double largest = -std::numeric_limits<double>::infinity();
    for (const auto& l : p.linearization.eigenvalues) largest = std::max(largest, l.real());
    out << "    " << std::setw(14) << full(p.value) << "  " << std::setw(22) << to_string(p.linearization.verdict)
        << "  max Re " << full(largest) << "\n";
  }
  if (sweep->thresholds.empty()) out << "  no change of verdict\n";
  for (const VerdictChange& t : sweep->thresholds)
    out << "  threshold " << sweep->range.name << " = " << base::number_text(t.value, 12) << ": " << to_string(t.from)
        << " -> " << to_string(t.to) << "\n";
}

void write_csv(const fs::path& path, const SweepResult& sweep) {
  std::size_t count = 0;
  for (const SweepPoint& p : sweep.points) count = std::max(count, p.linearization.eigenvalues.size());
  write_file_atomically(path.string(), [&](std::ostream& out) {
    out << sweep.range.name;
    for (std::size_t k = 1; k <= count; ++k) out << ",re" << k << ",im" << k;
    out << ",verdict\n";
    for (const SweepPoint& p : sweep.points) {
      out << base::shortest_text(p.value);
      const auto& ev = p.linearization.eigenvalues;
      for (std::size_t k = 0; k < count; ++k)
        if (k < ev.size()) out << ',' << base::shortest_text(ev[k].real()) << ',' << base::shortest_text(ev[k].imag());
        else out << ",,";
      out << ',' << to_string(p.linearization.verdict) << '\n';
    }
  });
}

/// The gnuplot script drawing Re λ and Im λ against the swept value, thresholds as dashed lines.
std::string stability_script(const SweepResult& sweep, const std::string& scene, std::size_t count,
                             const std::string& terminal, const std::string& output) {
  std::ostringstream g;
  g << terminal << "\nset output " << tools::gnuplot_string(output) << "\nset datafile separator ','\n"
    << "set key off\nset grid\nset xlabel " << tools::gnuplot_string(sweep.range.name) << " noenhanced\n"
    << "set multiplot layout 2,1 title "
    << tools::gnuplot_string("eigenvalues of " + scene + " against " + sweep.range.name) << " noenhanced\n";
  for (const VerdictChange& t : sweep.thresholds)
    g << "set arrow from " << base::shortest_text(t.value) << ", graph 0 to " << base::shortest_text(t.value)
      << ", graph 1 nohead dashtype 2\n";
  for (int part = 0; part < 2; ++part) {
    g << "set ylabel " << tools::gnuplot_string(part == 0 ? "Re(lambda)" : "Im(lambda)") << "\nplot ";
    for (std::size_t k = 0; k < count; ++k)
      g << (k ? ", " : "") << tools::gnuplot_string("stability.csv") << " every ::1 using 1:" << (2 + 2 * k + part)
        << " with points pointtype 7 pointsize 0.6 linecolor " << (k % 8 + 1);
    g << "\n";
  }
  g << "unset multiplot\nset output\n";
  return g.str();
}

/// Draws DIR/stability.svg and .png with gnuplot; returns a note when it cannot.
std::optional<std::string> plot_stability(const fs::path& dir, const SweepResult& sweep, const std::string& scene) {
  if (const auto missing = tools::gnuplot_missing()) return *missing + ": stability.svg/.png not drawn";
  std::size_t count = 0;
  for (const SweepPoint& p : sweep.points) count = std::max(count, p.linearization.eigenvalues.size());
  if (count == 0) return "no eigenvalues to draw";
  const std::string svg = "set terminal svg size 900,700 dynamic font 'sans,12' background rgb 'white'";
  const std::string png =
      "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) { set terminal pngcairo size 900,700 font 'sans,10' "
      "background rgb 'white' } else { set terminal png size 900,700 background rgb 'white' }";
  const fs::path script = dir / "stability.gp";
  {
    std::ofstream s(script);
    s << stability_script(sweep, scene, count, svg, "stability.svg") << "\n"
      << stability_script(sweep, scene, count, png, "stability.png");
  }
  std::string output;
  const int status = tools::run_gnuplot(dir, {"stability.gp"}, output);
  fs::remove(script);
  if (status != 0) return "gnuplot failed: " + output;
  return std::nullopt;
}

/// Writes DIR as a whole (nhc/io/atomic_directory.hpp): a temporary sibling directory moved into
/// place, or its files moved into an existing DIR under the output policy; an input is refused.
void write_directory(const std::string& target, const std::vector<std::string>& inputs, const Linearization& lin,
                     const std::optional<SweepResult>& sweep, std::vector<std::string>& notes) {
  AtomicDirectory out(target, inputs);
  const fs::path tmp = out.path();
  write_file_atomically((tmp / "linearize.json").string(), [&](std::ostream& o) { write_json(o, lin, sweep); });
  write_matrix_csv(tmp / "A.csv", lin.A, lin.states, lin.states);
  if (!lin.inputs.empty()) write_matrix_csv(tmp / "B.csv", lin.B, lin.states, lin.inputs);
  if (!lin.outputs.empty()) write_matrix_csv(tmp / "C.csv", lin.C, lin.outputs, lin.states);
  if (!lin.outputs.empty() && !lin.inputs.empty()) write_matrix_csv(tmp / "D.csv", lin.D, lin.outputs, lin.inputs);
  if (sweep) {
    write_csv(tmp / "stability.csv", *sweep);
    if (auto note = plot_stability(tmp, *sweep, lin.scene)) notes.push_back(*note);
  }
  out.commit();
}

}  // namespace

CommandRunner add_linearize_command(CLI::App& app) {
  auto flags = std::make_shared<LinearizeFlags>();
  CLI::App* sub = app.add_subcommand(
      "linearize",
      "linear stability of an equilibrium or steady motion: A on the constraint manifold, eigenvalues, "
      "verdict; --sweep for stability charts");
  sub->add_option("SCENE", flags->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", flags->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--at", flags->at, "NAME=VALUE: a parameter or initial value (th=0, ph'=5) at the operating point")
      ->allow_extra_args(false);
  sub->add_option("--keep", flags->keep,
                  "NAME,...: cyclic coordinates to keep as states (a controller holding a position needs them)")
      ->delimiter(',');
  sub->add_option("--states", flags->states,
                  "NAME,...: the reduced states, in this order (never eliminated by the hidden constraints)")
      ->delimiter(',');
  sub->add_option("--turn", flags->turn,
                  "ANGLE:X,Y: linearize about a steady turn (a relative equilibrium of the rotations of the X,Y plane "
                  "that move ANGLE), in the turning frame");
  sub->add_option("--sweep", flags->sweep, "NAME=a:b:n: n values from a to b of a parameter or initial value");
  sub->add_option("--format", flags->format, "text or json (default text)")->check(CLI::IsMember({"text", "json"}));
  sub->add_option(
      "-o,--output", flags->output,
      "directory for linearize.json, A.csv (B.csv with [inputs]) and, with --sweep, stability.csv/.svg/.png");

  return [flags]() {
    const Scene scene = load_scene(flags->scene_path);
    if (!flags->output.empty()) check_output_directory(flags->output, {flags->scene_path});
    const ModelKind kind = model_or_default(scene, flags->model);
    app::require_model_inputs(scene, kind);
    std::vector<PointOverride> overrides;
    std::vector<std::string> names;
    for (const std::string& text : flags->at) {
      overrides.push_back(parse_point_override(text));
      resolve_override(scene, overrides.back().name);  // unknown names are bad input, before any work
      names.push_back(overrides.back().name);
    }
    flag_rules::refuse_duplicates(names, "--at", "the value of");
    std::optional<SweepRange> range;
    if (!flags->sweep.empty()) {
      range = parse_sweep_range(flags->sweep);
      resolve_override(scene, range->name, "--sweep");
    }
    flag_rules::refuse_duplicates(flags->keep, "--keep", "the coordinate");
    flag_rules::refuse_duplicates(flags->states, "--states", "the state");
    LinearizeOptions options;
    options.keep = flags->keep;
    options.states = flags->states;
    if (!flags->turn.empty()) options.turn = parse_turn(flags->turn);
    const Linearizer linearizer(scene, kind, options);
    const Linearization lin = linearizer.at(overrides);
    std::optional<SweepResult> swept;
    if (range) swept = sweep(linearizer, overrides, *range);

    std::vector<std::string> notes;
    if (!flags->output.empty()) write_directory(flags->output, {flags->scene_path}, lin, swept, notes);
    if (flags->format == "json") write_json(std::cout, lin, swept);
    else write_text(std::cout, lin, swept);
    for (const std::string& note : notes) std::cerr << "nhc linearize: note: " << note << "\n";
    return kExitOk;
  };
}

}  // namespace nhc::cli
