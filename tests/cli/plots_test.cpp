// nhc simulate --plot and nhc compare end to end: the files, gnuplot without a word on stderr
// (run again here on the kept scripts), the CSV behind the pictures equal to the simulate CSV,
// Appell–Hamel's closed forms (docs/models.md) in compare.md, bad input, and atomic output
// directories (nhc/io/atomic_directory.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"

namespace {

namespace fs = std::filesystem;
using nhc::test::file_exists;
using nhc::test::read_file;
using nhc::test::Run;

/// nhc with the arguments, from the source directory, with this test's compile cache.
Run nhc_run(const std::string& args, const std::string& dir, const std::string& env = "") {
  return nhc::test::run(std::string("cd '") + NHC_SOURCE_DIR + "' && " + env + " NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                            "/tests/cli/nhc-cache' " + nhc::test::nhc_command() + " " + args,
                        dir);
}

/// gnuplot run again on a kept script in a copy of the directory: its standard error.
std::string gnuplot_stderr(const std::string& dir, const std::string& stem) {
  const std::string copy = dir + "-redraw";
  std::system(("rm -rf '" + copy + "' && cp -r '" + dir + "' '" + copy + "'").c_str());
  const Run r = nhc::test::run("cd '" + copy + "' && gnuplot " + stem + ".gp", copy);
  REQUIRE(r.exit_code == 0);
  return r.err;
}

/// The last row of a CSV file, as numbers, and the header.
std::pair<std::vector<std::string>, std::vector<double>> last_row(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line)) last = line;
  std::vector<std::string> names;
  std::vector<double> values;
  std::istringstream h(header), v(last);
  for (std::string cell; std::getline(h, cell, ',');) names.push_back(cell);
  for (std::string cell; std::getline(v, cell, ',');) values.push_back(std::strtod(cell.c_str(), nullptr));
  return {names, values};
}

bool has_png_signature(const std::string& path) { return read_file(path).substr(1, 3) == "PNG"; }

std::vector<std::string> siblings_named(const std::string& dir, const std::string& prefix) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(prefix, 0) == 0) found.push_back(e.path().filename().string());
  return found;
}

}  // namespace

TEST_CASE("simulate --plot draws the coordinates, path, multipliers and drift from the -o CSV", "[cli][plots]") {
  const std::string dir = nhc::test::scratch_dir("plots_simulate");
  const Run r = nhc_run(
      "simulate examples/appell_hamel.toml --plot-xy y,z -o '" + dir + "/run.csv' --plot '" + dir + "/plots'", dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const std::string plots = dir + "/plots/";
  // The CSV behind the pictures is the simulate CSV, byte for byte, and the scripts read it.
  REQUIRE(file_exists(plots + "appell_hamel_chetaev.csv"));
  CHECK(read_file(plots + "appell_hamel_chetaev.csv") == read_file(dir + "/run.csv"));
  for (const char* stem : {"coordinates", "path", "multipliers", "drift"}) {
    INFO(stem);
    CHECK(read_file(plots + stem + ".svg").find("<svg") != std::string::npos);
    CHECK(has_png_signature(plots + stem + ".png"));
    CHECK(read_file(plots + stem + ".gp").find("('appell_hamel_chetaev.csv')") != std::string::npos);
    CHECK(gnuplot_stderr(dir + "/plots", stem).empty());
    CHECK(read_file(plots + "plots.md").find(std::string("](") + stem + ".svg)") != std::string::npos);
  }
  // Axes and legends named: --plot-xy chose the plane.
  const std::string path = read_file(plots + "path.gp");
  CHECK(path.find("set xlabel ('y')") != std::string::npos);
  CHECK(path.find("set ylabel ('z')") != std::string::npos);
  CHECK(read_file(plots + "coordinates.gp").find("title ('x')") != std::string::npos);
  CHECK(read_file(plots + "multipliers.gp").find("title ('lambda1')") != std::string::npos);
  CHECK(read_file(plots + "drift.gp").find("set logscale y") != std::string::npos);
  CHECK(read_file(plots + "drift.gp").find("title ('energy: |I(t) - I(t0)|')") != std::string::npos);
  CHECK(siblings_named(dir, "plots.tmp").empty());
}

TEST_CASE("simulate --plot after a stop at t* still plots the motion up to there, exit 3", "[cli][plots]") {
  const std::string dir = nhc::test::scratch_dir("plots_simulate_stop");
  const Run r = nhc_run("simulate examples/appell_hamel.toml --t-end 0.4 --plot '" + dir + "/plots'", dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 3);
  CHECK(file_exists(dir + "/plots/coordinates.png"));
  CHECK(read_file(dir + "/plots/plots.md").find("The run stopped there") != std::string::npos);
}

TEST_CASE("compare runs every model from the same data and reports what differs", "[cli][plots]") {
  const std::string dir = nhc::test::scratch_dir("plots_compare");
  const Run r = nhc_run("compare examples/appell_hamel.toml --t-end 0.4 -o '" + dir + "/out'", dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const std::string out = dir + "/out/";
  const std::string md = read_file(out + "compare.md");
  const char* models[] = {"vakonomic", "chetaev", "holder", "suslov"};

  // One CSV per model, equal to nhc simulate's with the same settings.
  for (const char* model : models) {
    INFO(model);
    const Run s = nhc_run(std::string("simulate examples/appell_hamel.toml --t-end 0.4 --model ") + model + " -o '" +
                              dir + "/" + model + ".csv'",
                          dir);
    // The solved models stop where x'^2 + y'^2 reaches 0 (t = 0.285); suslov only monitors it.
    REQUIRE(s.exit_code == (std::string(model) == "suslov" ? 0 : 3));
    CHECK(read_file(out + model + ".csv") == read_file(dir + "/" + model + ".csv"));
  }
  // Overlaid plots, a legend entry per model, gnuplot silent.
  for (const char* stem : {"coordinate_x", "coordinate_y", "coordinate_z", "path", "invariant_energy"}) {
    INFO(stem);
    CHECK(has_png_signature(out + stem + ".png"));
    const std::string svg = read_file(out + stem + ".svg");
    for (const char* model : models) CHECK(svg.find(std::string(">") + model + "<") != std::string::npos);
    CHECK(gnuplot_stderr(dir + "/out", stem).empty());
    CHECK(md.find(std::string("](") + stem + ".svg)") != std::string::npos);
  }

  // Appell–Hamel closed forms (docs/models.md), with k = b/a = 1/2, v0 = |(1, 1/2)|, g = 9.81, m = 1:
  // chetaev stops at t* = v0 (a² + b²)/(g a b); its λ = m g/(1 + k²) and z' = k v0 at t0.
  const double v0 = std::sqrt(1.25), k = 0.5, g = 9.81;
  const double t_star = v0 * 1.25 / (g * 0.5);
  const auto [names, last] = last_row(out + "chetaev.csv");
  CHECK(last.front() == Approx(t_star).epsilon(1e-6));  // the run stops just before v = 0
  std::ostringstream lambda, z_prime;
  lambda << "| lambda1 | 0 | 0 | " << g / (1 + k * k) << " |";
  z_prime << "| z' |  | " << std::setprecision(6) << k * v0;
  CHECK(md.find(lambda.str()) != std::string::npos);
  CHECK(md.find(z_prime.str()) != std::string::npos);
  CHECK(md.find("| chetaev | stopped at a singularity at t = 0.284922") != std::string::npos);
  CHECK(md.find("| suslov | ran to the end") != std::string::npos);
  // Suslov starts on the constraint (its monitored constraint completes z'(0)) but does not
  // impose it: z'' = -g, x'' = y'' = 0 (models.md), so f1 = z' - k v0 = -g t grows to g t_end.
  CHECK(md.find("**z''** differs: -1.962 (vakonomic, chetaev, holder); -9.81 (suslov).") != std::string::npos);
  CHECK(md.find("| chetaev – suslov | ") != std::string::npos);
  std::ostringstream suslov_drift;
  suslov_drift << "| suslov | constraint f1: z' - b/a*sqrt(x'^2 + y'^2) | ≈ 0 | " << std::setprecision(4) << g * 0.4
               << " |";
  CHECK(md.find(suslov_drift.str()) != std::string::npos);
  CHECK(md.find("## Wall times") != std::string::npos);
}

TEST_CASE("compare lists models that do not apply with their reason", "[cli][plots]") {
  // A scene without `dependent`: the suslov model needs one dependent coordinate per constraint.
  const std::string dir = nhc::test::scratch_dir("plots_compare_not_applicable");
  const std::string scene = dir + "/no_dependent.toml";
  std::ofstream(scene) << "name = \"no_dependent\"\ncoordinates = [\"x\", \"y\"]\n"
                          "lagrangian = \"(x'^2 + y'^2)/2\"\nconstraints = [\"x' - y\"]\n"
                          "[initial]\nx = [0.0, 1.0]\ny = [1.0]\nlambda1 = [0.0]\n"
                          "[simulate]\nt_end = 0.5\n";
  const Run r = nhc_run("compare '" + scene + "' -o '" + dir + "/out'", dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const std::string md = read_file(dir + "/out/compare.md");
  CHECK(md.find("Models that do not apply, or stop at t0:") != std::string::npos);
  CHECK(md.find("- **suslov**: does not apply: ") != std::string::npos);
  CHECK_FALSE(file_exists(dir + "/out/suslov.csv"));
}

TEST_CASE("compare and simulate --plot refuse bad input with exit 2 and write nothing", "[cli][plots]") {
  const std::string dir = nhc::test::scratch_dir("plots_bad_input");
  struct Case {
    std::string args, words;
  } cases[] = {
      {"compare examples/appell_hamel.toml --models chetaev,kepler -o out", "--models"},
      {"compare examples/appell_hamel.toml --plot-xy x,w -o out", "--plot-xy: error: 'x,w': 'w' is not a coordinate"},
      {"compare examples/appell_hamel.toml --plot-xy x -o out", "--plot-xy: error: 'x': expected two coordinate names"},
      {"compare examples/appell_hamel.toml --t-end -1 -o out", "--t-end: error:"},
      {"compare examples/appell_hamel.toml", "-o"},
      {"simulate examples/appell_hamel.toml --plot out --plot-xy x,x", "two different coordinates"},
      {"simulate examples/appell_hamel.toml --plot-xy x,y", "--plot"},
  };
  for (const Case& c : cases) {
    INFO(c.args);
    const Run r = nhc_run(c.args.substr(0, c.args.find(" -o out")) +
                              (c.args.find(" -o out") != std::string::npos ? " -o '" + dir + "/out'" : "") + "",
                          dir);
    INFO(r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(c.words) != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(file_exists(dir + "/out"));
  }
}

TEST_CASE("output directories: the user's other files kept, outputs updated, untouched on failure", "[cli][plots]") {
  const std::string dir = nhc::test::scratch_dir("plots_atomic");
  // An existing directory keeps the files that are not outputs (nhc/io/atomic_directory.hpp).
  fs::create_directories(dir + "/foreign");
  std::ofstream(dir + "/foreign/notes.txt") << "mine";
  Run r = nhc_run("compare examples/particle.toml -o '" + dir + "/foreign'", dir);
  CHECK(r.exit_code == 0);
  CHECK(read_file(dir + "/foreign/notes.txt") == "mine");
  CHECK(file_exists(dir + "/foreign/compare.md"));

  // An earlier output's files are replaced by name.
  r = nhc_run("compare examples/particle.toml --models chetaev,holder -o '" + dir + "/out'", dir);
  REQUIRE(r.exit_code == 0);
  const std::string first = read_file(dir + "/out/compare.md");
  r = nhc_run("compare examples/particle.toml --models chetaev -o '" + dir + "/out'", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(read_file(dir + "/out/compare.md") != first);
  CHECK(read_file(dir + "/out/compare.md").find("holder") == std::string::npos);
  CHECK(file_exists(dir + "/out/chetaev.csv"));

  // gnuplot failing half-way (a stand-in that answers --version and nothing else): exit 1,
  // the earlier output untouched, no temporary directory left.
  const std::string before = read_file(dir + "/out/compare.md");
  fs::create_directories(dir + "/bin");
  std::ofstream(dir + "/bin/gnuplot") << "#!/bin/sh\n[ \"$1\" = --version ] && exec echo 'gnuplot 5.4'\n"
                                         "echo 'broken gnuplot' >&2\nexit 1\n";
  fs::permissions(dir + "/bin/gnuplot", fs::perms::owner_all);
  for (const std::string target : {"out", "new"}) {
    r = nhc_run("compare examples/particle.toml -o '" + dir + "/" + target + "'", dir,
                "PATH='" + dir + "/bin':\"$PATH\"");
    INFO(r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("broken gnuplot") != std::string::npos);
  }
  CHECK(read_file(dir + "/out/compare.md") == before);
  CHECK_FALSE(file_exists(dir + "/new"));
  CHECK(siblings_named(dir, "out.tmp").empty());
  CHECK(siblings_named(dir, "new.tmp").empty());
}
