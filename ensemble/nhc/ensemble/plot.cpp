// Maps of an ensemble's outcome with gnuplot (plot.hpp).
#include "nhc/ensemble/plot.hpp"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/io/printable.hpp"
#include "nhc/io/temporary_files.hpp"
#include "nhc/tools/gnuplot.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::ensemble {

namespace fs = std::filesystem;

namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

std::string joined_names(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

int index_of(const std::vector<std::string>& names, const std::string& name) {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<int>(k);
  return -1;
}

}  // namespace

std::vector<std::string> outcome_names(const EnsembleInfo& info) {
  std::vector<std::string> names{"t_stop", "steps", "seconds", "drift:hidden"};
  for (const std::string& s : info.state_names) names.push_back("final:" + s);
  for (const std::string& s : info.invariant_names) names.push_back("drift:" + s);
  return names;
}

std::vector<double> outcome_values(const EnsembleResults& results, const std::string& outcome,
                                   const std::string& flag) {
  const EnsembleInfo& info = results.info;
  std::function<double(const RunRecord&)> value;
  if (outcome == "t_stop") {
    value = [](const RunRecord& r) { return r.t_stop; };
  } else if (outcome == "steps") {
    value = [](const RunRecord& r) { return static_cast<double>(r.steps); };
  } else if (outcome == "seconds") {
    value = [](const RunRecord& r) { return r.seconds; };
  } else if (outcome == "drift:hidden") {
    value = [](const RunRecord& r) { return r.hidden_drift; };
  } else if (outcome.rfind("final:", 0) == 0 && index_of(info.state_names, outcome.substr(6)) >= 0) {
    const auto k = static_cast<std::size_t>(index_of(info.state_names, outcome.substr(6)));
    value = [k](const RunRecord& r) { return r.final_state.at(k); };
  } else if (outcome.rfind("drift:", 0) == 0 && index_of(info.invariant_names, outcome.substr(6)) >= 0) {
    const auto k = static_cast<std::size_t>(index_of(info.invariant_names, outcome.substr(6)));
    value = [k](const RunRecord& r) { return r.invariant_drift.at(k); };
  } else {
    throw InputError({flag + " " + printable(outcome), 0, 0},
                     "unknown outcome; this ensemble has " + printable(joined_names(outcome_names(info))));
  }
  std::vector<double> out;
  for (const RunRecord& r : results.records) {
    const bool has = r.outcome == Outcome::ok || r.outcome == Outcome::singular ||
                     (r.outcome == Outcome::failed && outcome == "t_stop");
    out.push_back(has ? value(r) : kMissing);
  }
  return out;
}

std::string default_plot_stem(const std::string& h5_path, const std::string& outcome) {
  fs::path p(h5_path);
  if (p.extension() == ".h5") p.replace_extension();
  std::string tag;
  for (char c : outcome) tag += std::isalnum(static_cast<unsigned char>(c)) ? c : c == '\'' ? 'p' : '_';
  return p.string() + "_" + tag;
}

std::vector<std::string> plot_outcome(const EnsembleResults& results, const std::string& outcome,
                                      const std::string& stem, const std::string& flag,
                                      const std::vector<std::string>& inputs) {
  const Design& d = results.info.design;
  const std::vector<double> z = outcome_values(results, outcome, flag);
  const std::size_t nv = d.variables.size();
  if (nv < 1 || nv > 2)
    throw InputError({flag + " " + outcome, 0, 0},
                     "maps need a design of one or two variables, this one has " + std::to_string(nv));
  if (const auto missing = tools::gnuplot_missing()) throw EnvironmentError(*missing);
  for (const char* ext : {".dat", ".gp", ".svg", ".png"}) check_output_file(stem + ext, inputs);

  const bool heat_map = nv == 2 && d.kind == Design::Kind::grid;
  write_file_atomically(stem + ".dat", [&](std::ostream& out) {
    out << tools::gnuplot_comment(joined_names(d.names()) + " " + outcome + " (" + results.info.scene + ", " +
                                  results.info.model + ")");
    for (long run = 0; run < d.runs; ++run) {
      // A heat map's rows are separated by blank lines (gnuplot's grid format).
      if (heat_map && run > 0 && run % d.grid_shape[1] == 0) out << "\n";
      for (std::size_t j = 0; j < nv; ++j) out << base::shortest_text(d.row(run)[j]) << ' ';
      const double value = z[static_cast<std::size_t>(run)];
      out << base::shortest_text(std::isfinite(value) ? value : kMissing) << "\n";
    }
  });

  const std::string dat = fs::path(stem + ".dat").filename().string();
  const std::string title = outcome + ": " + results.info.scene + " (" + results.info.model + ")";
  std::ostringstream plot;
  plot << "set datafile missing 'nan'\nset title " << tools::gnuplot_string(title) << " noenhanced\n"
       << "set xlabel " << tools::gnuplot_string(d.variables[0].name) << " noenhanced\n";
  if (nv == 1) {
    plot << "set ylabel " << tools::gnuplot_string(outcome) << " noenhanced\nset grid\nunset key\n"
         << "plot " << tools::gnuplot_string(dat) << " using 1:2 with "
         << (d.kind == Design::Kind::grid ? "linespoints pointtype 7 pointsize 0.5"
                                          : "points pointtype 7 pointsize 0.5")
         << "\n";
  } else {
    plot << "set ylabel " << tools::gnuplot_string(d.variables[1].name) << " noenhanced\n"
         << "set cblabel " << tools::gnuplot_string(outcome)
         << " noenhanced\nset palette rgbformulae 33,13,10\nunset key\n";
    if (heat_map) plot << "set autoscale fix\nplot " << tools::gnuplot_string(dat) << " using 1:2:3 with image\n";
    else
      plot << "plot " << tools::gnuplot_string(dat) << " using 1:2:3 with points pointtype 7 pointsize 0.6 palette\n";
  }
  const std::string suffix = ".tmp" + std::to_string(::getpid());
  auto script = [&](const std::string& svg, const std::string& png) {
    std::ostringstream g;
    g << "set terminal svg size 900,640 dynamic enhanced font 'sans,12' background rgb 'white'\n"
      << "set output " << tools::gnuplot_string(svg) << "\n"
      << plot.str() << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
      << "  set terminal pngcairo size 900,640 enhanced font 'sans,10' background rgb 'white'\n"
      << "} else {\n  set terminal png size 900,640 enhanced background rgb 'white'\n}\n"
      << "set output " << tools::gnuplot_string(png) << "\nreplot\nset output\n";
    return g.str();
  };
  const std::string name = fs::path(stem).filename().string();
  write_file_atomically(stem + ".gp", [&](std::ostream& out) { out << script(name + ".svg", name + ".png"); });
  const fs::path dir = fs::path(stem).parent_path().empty() ? fs::path(".") : fs::path(stem).parent_path();
  const TemporaryFile script_file(stem + ".gp" + suffix), svg(stem + ".svg" + suffix), png(stem + ".png" + suffix);
  {
    std::ofstream out(script_file.path());
    out << script(name + ".svg" + suffix, name + ".png" + suffix);
  }
  std::string messages;
  const int status = tools::run_gnuplot(dir, {fs::path(script_file.path()).filename().string()}, messages);
  if (status != 0) throw std::runtime_error("gnuplot failed on " + stem + ".gp: " + messages);
  std::vector<std::string> written;
  for (const char* ext : {".svg", ".png"}) {
    const std::string target = stem + ext;
    if (std::rename((target + suffix).c_str(), target.c_str()) != 0)
      throw std::runtime_error("gnuplot did not write " + target + ": " + messages);
    written.push_back(target);
  }
  return written;
}

}  // namespace nhc::ensemble
