// The first hour of a new user: what went wrong for one on Appell–Hamel
// (examples/appell_hamel.toml, constraint f1 = z' − (b/a)·sqrt(x'² + y'²), b/a = 1/2).
// One initial-point rule and one message in analyze and simulate (nhc/base/initial_point.hpp),
// no compile and no file on an inconsistent start, --max-steps, -o -, --repair-initial.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using Catch::Matchers::Contains;
using nhc::test::file_exists;
using nhc::test::read_file;
using nhc::test::Run;

Run nhc_run(const std::string& args, const std::string& dir) {
  return nhc::test::run(std::string("cd '") + NHC_SOURCE_DIR + "' && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                            "/tests/cli/nhc-cache' " + nhc::test::nhc_command() + " " + args,
                        dir);
}

/// examples/appell_hamel.toml with `z = [...]` replaced, written to dir/name.
std::string appell_hamel_with_z(const std::string& dir, const std::string& name, const std::string& z) {
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml");
  text = std::regex_replace(text, std::regex(R"(\nz = \[0\.0\]\n)"), "\nz = " + z + "\n");
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// The error lines of a run (standard error without the notes).
std::string first_error(const std::string& err) { return err.substr(0, err.find('\n')); }

std::vector<double> csv_row(const std::string& csv, int row) {
  std::istringstream in(csv);
  std::string line;
  for (int i = 0; i <= row; ++i) std::getline(in, line);
  std::getline(in, line);
  std::vector<double> values;
  std::istringstream fields(line);
  std::string field;
  while (std::getline(fields, field, ',')) values.push_back(std::stod(field));
  return values;
}

}  // namespace

TEST_CASE("velocities typed to ten digits are accepted by analyze and simulate alike", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_ten_digits");
  // z'(0) = sqrt(1.25)/2 = 0.559016994374947…: ten digits miss f1 by 2.5e-11 < atol + rtol = 1.01e-8.
  const std::string scene = appell_hamel_with_z(dir, "ten_digits.toml", "[0.0, 0.5590169944]");
  CHECK(nhc_run("analyze '" + scene + "' -m chetaev", dir).exit_code == 0);
  const Run sim = nhc_run("simulate '" + scene + "' -o '" + dir + "/out.csv'", dir);
  CHECK(sim.exit_code == 0);
  CHECK_THAT(sim.out, Contains("201 rows"));
}

TEST_CASE("a given value that misses a hidden constraint gets the same words in analyze and simulate", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_three_digits");
  const std::string scene = appell_hamel_with_z(dir, "three_digits.toml", "[0.0, 0.559]");
  const Run analyze = nhc_run("analyze '" + scene + "' -m chetaev", dir);
  const Run simulate = nhc_run("simulate '" + scene + "' -o '" + dir + "/out.csv'", dir);
  CHECK(analyze.exit_code == 3);
  CHECK(simulate.exit_code == 3);
  CHECK(first_error(analyze.err) == first_error(simulate.err));
  // The constraint, its residual 0.559 − sqrt(1.25)/2, the tolerance rule and the given values.
  CHECK_THAT(simulate.err, Contains("hidden constraint f1") && Contains("residual -1.699437495e-05") &&
                               Contains("atol + rtol") && Contains("x' = 1") && Contains("y' = 0.5") &&
                               Contains("z' = 0.559"));
  // Checked before compiling: no summary, no file.
  CHECK(simulate.out.empty());
  CHECK_FALSE(file_exists(dir + "/out.csv"));
}

TEST_CASE("the runtime applies the same rule when --atol and --rtol loosen it", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_loose");
  const std::string scene = appell_hamel_with_z(dir, "three_digits.toml", "[0.0, 0.559]");
  // A miss of 1.7e-5 is within atol = 1e-4.
  CHECK(nhc_run("simulate '" + scene + "' --atol 1e-4 --rtol 1e-6", dir).exit_code == 0);
}

TEST_CASE("simulate --repair-initial starts on the constraint", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_repair");
  const std::string scene = appell_hamel_with_z(dir, "three_digits.toml", "[0.0, 0.559]");
  const Run r = nhc_run("simulate '" + scene + "' --repair-initial -o -", dir);
  REQUIRE(r.exit_code == 0);
  // -o -: the CSV alone on standard output, the summary on standard error.
  CHECK(r.out.rfind("t,x,x'", 0) == 0);
  CHECK_THAT(r.err, Contains("nhc simulate:") && Contains("standard output"));
  // t,x,x',x'',y,y',y'',z,z',...: f1 = z' − sqrt(x'² + y'²)/2 at the first row.
  const std::vector<double> row = csv_row(r.out, 0);
  REQUIRE(row.size() > 8);
  CHECK(std::abs(row[8] - 0.5 * std::hypot(row[2], row[5])) < 1e-12);
  CHECK(std::abs(row[8] - 0.559) < 1e-4);
}

TEST_CASE("simulate --max-steps stops with the limit and the time reached", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_max_steps");
  const Run r = nhc_run("simulate examples/appell_hamel.toml --max-steps 10 -o '" + dir + "/out.csv'", dir);
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.err, Contains("step limit (10 steps)") && Contains("reached at t = "));
  CHECK_THAT(r.out, Contains("the motion up to the failure"));
  CHECK(nhc_run("simulate examples/appell_hamel.toml --max-steps 0", dir).exit_code == 2);
}

TEST_CASE("simulate without -o says that no CSV was written", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_no_output");
  const Run r = nhc_run("simulate examples/particle.toml", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("no CSV written"));
}

TEST_CASE("the suslov model without 'dependent' is bad input located in the scene", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_no_dependent");
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml");
  text = std::regex_replace(text, std::regex(R"(\ndependent = \["z"\]\n)"), "\n");
  const std::string scene = dir + "/no_dependent.toml";
  std::ofstream(scene) << text;
  const std::regex located("^" + scene +
                           R"(:\d+:\d+: error: the suslov model needs one dependent coordinate per constraint.*\n$)");
  for (const std::string command : {"simulate", "derive", "analyze", "generate"}) {
    INFO(command);
    const Run r =
        nhc_run(command + " '" + scene + "' --model suslov" + (command == "generate" ? " -o '" + dir + "'" : ""), dir);
    CHECK(r.exit_code == 2);
    CHECK(std::regex_match(r.err, located));
  }
  // The other models of the scene are unaffected: analyze reports suslov as a note, exit 0.
  const Run all = nhc_run("analyze '" + scene + "'", dir);
  CHECK(all.exit_code == 0);
  CHECK_THAT(all.err, Contains("nhc: note: the suslov model is not applicable"));
}

TEST_CASE("analyze exits 3 only when a requested model fails", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_per_model");
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel_vakonomic_singular.toml");
  text = std::regex_replace(text, std::regex(R"(\nmodels = \["vakonomic"\]\n)"),
                            "\nmodels = [\"vakonomic\", \"chetaev\"]\n");
  const std::string scene = dir + "/two_models.toml";
  std::ofstream(scene) << text;
  const Run both = nhc_run("analyze '" + scene + "'", dir);  // default model: chetaev
  CHECK(both.exit_code == 0);
  CHECK_THAT(both.out, Contains("vakonomic:") && Contains("chetaev:"));
  CHECK_THAT(both.err, Contains("nhc: note: the system Jacobian of the vakonomic model is singular"));
  CHECK(nhc_run("analyze '" + scene + "' --model chetaev", dir).exit_code == 0);
  const Run vakonomic = nhc_run("analyze '" + scene + "' --model vakonomic --model chetaev", dir);
  CHECK(vakonomic.exit_code == 3);
  CHECK_THAT(vakonomic.err, Contains("nhc: error: the system Jacobian of the vakonomic model is singular"));
}

TEST_CASE("parameters set by --set P=V in simulate, analyze, generate and derive", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_set");
  // g = 0, b = 1/4: z'(0) = (b/a)·|(1, 1/2)| = sqrt(1.25)/4 and Chetaev's v' = −g k/(1 + k²) = 0,
  // uniform motion (docs/models.md), with the model compiled for the scene's values reused.
  const Run sim = nhc_run("simulate examples/appell_hamel.toml --set g=0 --set b=0.25 -o -", dir);
  REQUIRE(sim.exit_code == 0);
  const std::vector<double> first = csv_row(sim.out, 0), last = csv_row(sim.out, 200);
  REQUIRE(first.size() > 9);
  CHECK(std::abs(first[8] - std::sqrt(1.25) / 4) < 1e-12);
  CHECK(std::abs(last[2] - 1.0) < 1e-9);  // x' stays 1
  CHECK(std::abs(last[1] - 0.2) < 1e-9);  // x = t
  CHECK(std::abs(last[7] - 0.2 * std::sqrt(1.25) / 4) < 1e-9);

  const Run analyze = nhc_run("analyze examples/appell_hamel.toml -m chetaev --set b=2", dir);
  CHECK(analyze.exit_code == 0);
  CHECK_THAT(analyze.out, Contains("z' = 2.236067977"));  // 2·sqrt(1.25)

  const Run generate = nhc_run("generate examples/appell_hamel.toml --set b=2 -q -o '" + dir + "'", dir);
  CHECK(generate.exit_code == 0);
  CHECK_THAT(read_file(dir + "/appell_hamel_chetaev.hpp"), Contains("default_parameters[n_parameters] = {1.0, 2.0,"));

  CHECK(nhc_run("derive examples/appell_hamel.toml --set b=2", dir).exit_code == 0);
  for (const std::string command : {"simulate", "derive", "analyze", "generate"}) {
    INFO(command);
    const Run unknown = nhc_run(command + " examples/appell_hamel.toml --set q=1 -o '" + dir + "/x'", dir);
    CHECK(unknown.exit_code == 2);
    CHECK_THAT(unknown.err, Contains("--set: error: q=1: 'q' is not a parameter of the scene"));
    // One line, the flag named once (its location), the assignment quoted as written (as --initial).
    const Run nan = nhc_run(command + " examples/appell_hamel.toml --set b=abc", dir);
    CHECK(nan.exit_code == 2);
    CHECK(first_error(nan.err) == "--set: error: b=abc: 'abc' is not a number");
    const Run bare = nhc_run(command + " examples/appell_hamel.toml --set b", dir);
    CHECK(bare.exit_code == 2);
    CHECK(first_error(bare.err) == "--set: error: b: expected NAME=VALUE");
  }
}

TEST_CASE("a t0 from --initial after the scene's t_end asks for --t-end in every command that runs", "[cli][initial]") {
  // examples/appell_hamel.toml: [simulate] t_end = 0.2; the rule is app::run_t_end, as simulate's.
  const std::string dir = nhc::test::scratch_dir("first_hour_t_end_after_t0");
  // Located at the scene (simulate, report) or the flag (compare, ensemble); the words are one rule's.
  const auto message = [](const std::string& err) {
    const std::string line = first_error(err);
    const std::size_t at = line.find(": error: ");
    return at == std::string::npos ? line : line.substr(at + 9);
  };
  const std::string wanted = "the scene's [simulate] t_end 0.2 is not after t0 = 1: give --t-end";
  for (const std::string command : {"simulate", "report", "compare", "ensemble"}) {
    INFO(command);
    const std::string extra = command == "ensemble" ? " --vary b=1:2:2" : "";
    const Run refused =
        nhc_run(command + " examples/appell_hamel.toml --initial t0=1" + extra + " -o '" + dir + "/x'", dir);
    CHECK(refused.exit_code == 2);
    CHECK(message(refused.err) == wanted);
    const Run given = nhc_run(
        command + " examples/appell_hamel.toml --initial t0=1 --t-end 0.5" + extra + " -o '" + dir + "/x'", dir);
    CHECK(given.exit_code == 2);
    CHECK(message(given.err) == "--t-end 0.5 must be after t0 = 1");
  }
}

TEST_CASE("a parameter the scene computes from others follows --set of those and refuses its own",
          "[cli][parameters]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_derived_parameters");
  // A wheel (mass mw, radius r, Ja = mw r^2/2) under a body mb, rolling: x' = r th', and
  // x'(0) = r*Ja written through the computed parameter.
  const std::string scene = dir + "/wheel.toml";
  std::ofstream(scene) << "name = \"wheel\"\ncoordinates = [\"x\", \"th\"]\n"
                          "lagrangian = \"m/2*x'^2 + Ja/2*th'^2\"\nconstraints = [\"x' - r*th'\"]\n"
                          "[parameters]\nJa = \"mw*r^2/2\"\nm = \"mw + mb\"\nmw = 2.0\nmb = 1.0\nr = 0.5\n"
                          "[initial]\nx = [0.0, \"r*Ja\"]\nth = [0.0]\nlambda1 = [0.0]\n"
                          "[simulate]\nmodel = \"chetaev\"\nt_end = 0.5\noutputs = 2\n";
  const Run plain = nhc_run("simulate '" + scene + "' -o -", dir);
  REQUIRE(plain.exit_code == 0);
  CHECK(std::abs(csv_row(plain.out, 0)[2] - 0.5 * 0.25) < 1e-15);
  const Run heavier = nhc_run("simulate '" + scene + "' --set mw=4 -o -", dir);
  REQUIRE(heavier.exit_code == 0);
  CHECK(std::abs(csv_row(heavier.out, 0)[2] - 0.5 * 0.5) < 1e-15);       // Ja = 4 * 0.25 / 2
  CHECK(std::abs(csv_row(heavier.out, 2)[1] - 0.5 * 0.5 * 0.5) < 1e-9);  // uniform rolling
  const Run refused = nhc_run("simulate '" + scene + "' --set Ja=1 -o -", dir);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("--set: error: Ja=1: the scene computes 'Ja' from other parameters"));
}

TEST_CASE("output times and columns of simulate", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_outputs");
  // [simulate] outputs = 4: five rows.
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml");
  text = std::regex_replace(text, std::regex(R"(\nt_end = 0\.2\n)"), "\nt_end = 0.2\noutputs = 4\n");
  const std::string scene = dir + "/four.toml";
  std::ofstream(scene) << text;
  const Run four = nhc_run("simulate '" + scene + "' -o -", dir);
  REQUIRE(four.exit_code == 0);
  CHECK(std::count(four.out.begin(), four.out.end(), '\n') == 6);

  // --output-times START:STEP:END, --columns: t first, then the named ones in order. Chetaev:
  // z'' = k v' = −(b/a)·g k/(1 + k²) = −1.962 (docs/models.md), so z'(t) = z'(0) − 1.962 t.
  const Run r = nhc_run("simulate examples/appell_hamel.toml --output-times 0:0.05:0.2 --columns \"z',x\" -o -", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.rfind("t,z',x\n", 0) == 0);
  CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 6);
  const std::vector<double> row = csv_row(r.out, 2);  // t = 0.1
  REQUIRE(row.size() == 3);
  CHECK(std::abs(row[0] - 0.1) < 1e-15);
  CHECK(std::abs(row[1] - (std::sqrt(1.25) / 2 - 0.1962)) < 1e-8);

  const Run list = nhc_run("simulate examples/appell_hamel.toml --output-times 0,0.1,0.15 --columns x -o -", dir);
  REQUIRE(list.exit_code == 0);
  CHECK(std::count(list.out.begin(), list.out.end(), '\n') == 4);
  CHECK_THAT(list.err, Contains("t from 0 to 0.15"));

  CHECK(nhc_run("simulate examples/appell_hamel.toml --columns w", dir).exit_code == 2);
  CHECK(nhc_run("simulate examples/appell_hamel.toml --output-times 0:0.03:0.2", dir).exit_code == 2);
  CHECK(nhc_run("simulate examples/appell_hamel.toml --output-times 0.1,0.05", dir).exit_code == 2);
  CHECK(nhc_run("simulate examples/appell_hamel.toml --output-times 0:0.1:0.2 --t-end 1", dir).exit_code == 2);
}

TEST_CASE("report -o DIR on bad input leaves no directory", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_report_bad");
  for (const std::string args : {"tests/bad/empty_models.toml", "examples/particle.toml --set q=1",
                                 "examples/particle.toml --tolerances 1e-3:1e-20"}) {
    INFO(args);
    const Run r = nhc_run("report " + args + " -o '" + dir + "/report'", dir);
    CHECK(r.exit_code == 2);
    CHECK_FALSE(file_exists(dir + "/report"));
  }
}

TEST_CASE("invariant drift is relative to the invariant's size along the run, absolute below a floor", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_invariant_scale");
  // The particle (examples/particle.toml): speed² = 1 + 4 + 4 = 9 along the run; the constraint
  // q'·q'' itself as an "invariant" is 0 up to rounding, whose relative drift would be noise.
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/particle.toml");
  text += "power = \"q1'*q1'' + q2'*q2'' + q3'*q3''\"\n";
  // q1 = t starts at exactly 0 and grows to 1: its drift is relative to 1, not to I(t0) = 0.
  text += "position = \"q1\"\n";
  const std::string scene = dir + "/particle.toml";
  std::ofstream(scene) << text;
  const Run r = nhc_run("simulate '" + scene + "'", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("invariant speed_squared: max change") && Contains("to its largest size 9)"));
  CHECK_THAT(r.out, Contains("invariant power: max change") && Contains("(absolute: the invariant stays below 1e-08)"));
  CHECK_THAT(r.out, Contains("invariant position: max change 1 (relative 1 to its largest size 1)\n"));
}

TEST_CASE("the suslov run starts where analyze does and shows its monitored constraint, zero at t0", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_suslov_monitored");
  const Run r = nhc_run("simulate examples/appell_hamel.toml --model suslov -o '" + dir + "/s.csv'", dir);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("monitored constraint f1 = z' - b/a*sqrt(x'^2 + y'^2) (CSV column constraint:f1): "
                             "value at t0 0, max |f1| 1.96 (not enforced by the suslov model)"));
  // At t0 the run starts on f1 = z' − (b/a)·sqrt(x'² + y'²) = 0, evaluated here from the CSV.
  const std::string csv = read_file(dir + "/s.csv");
  CHECK(csv.rfind("t,x,x',x'',y,y',y'',z,z',z'',constraint:f1,", 0) == 0);  // no multiplier
  const std::vector<double> row = csv_row(csv, 0);
  REQUIRE(row.size() > 10);
  CHECK(std::abs(row[8] - 0.5 * std::hypot(row[2], row[5])) < 1e-12);
  CHECK(std::abs(row[10]) < 1e-12);
  // The start point is the one nhc analyze --model suslov reports: z' solved, not set to 0.
  const Run analyze = nhc_run("analyze examples/appell_hamel.toml --model suslov", dir);
  REQUIRE(analyze.exit_code == 0);
  std::smatch z_prime;
  REQUIRE(std::regex_search(analyze.out, z_prime, std::regex(R"(z' = ([0-9.eE+-]+) \(solved\))")));
  CHECK(std::abs(row[8] - std::stod(z_prime[1].str())) < 1e-9);
  CHECK(std::abs(row[8] - std::sqrt(1.25) / 2) < 1e-12);
}

TEST_CASE("repair moves only the values not pinned by [initial] fixed, and writes them back", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_pinned_repair");
  const std::string scene = appell_hamel_with_z(dir, "pinned.toml", "[0.0, 0.559]\nfixed = [\"x'\", \"z'\"]");
  // x' = 1 and z' = 0.559 pinned: f1 = 0 leaves y' = sqrt((2 z')² − x'²) (b/a = 1/2).
  const double y_prime = std::sqrt(4 * 0.559 * 0.559 - 1);
  const Run sim = nhc_run("simulate '" + scene + "' --repair-initial -o -", dir);
  REQUIRE(sim.exit_code == 0);
  const std::vector<double> row = csv_row(sim.out, 0);
  CHECK(row[2] == 1.0);
  CHECK(row[8] == 0.559);
  CHECK(std::abs(row[5] - y_prime) < 1e-12);

  const std::string written = dir + "/initial.toml";
  const Run analyze =
      nhc_run("analyze '" + scene + "' -m chetaev --repair-initial --write-initial '" + written + "'", dir);
  REQUIRE(analyze.exit_code == 0);
  CHECK_THAT(analyze.out, Contains("repaired y'"));
  const std::string table = read_file(written);
  CHECK_THAT(table, Contains("[initial]") && Contains("x = [0.0, 1.0]") && Contains("z = [0.0, 0.559]") &&
                        Contains("fixed = [\"x'\", \"z'\"]"));
  // The written table, pasted into the scene, is consistent: simulate accepts it without repair.
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml");
  text = text.substr(0, text.find("[initial]")) + table.substr(table.find("[initial]")) + "lambda1 = [0.0]\n" +
         text.substr(text.find("[simulate]") - 1);
  const std::string repaired = dir + "/repaired.toml";
  std::ofstream(repaired) << text;
  const Run again = nhc_run("simulate '" + repaired + "' -o -", dir);
  REQUIRE(again.exit_code == 0);
  CHECK(std::abs(csv_row(again.out, 0)[5] - y_prime) < 1e-12);

  CHECK(nhc_run("analyze '" + scene + "' --write-initial '" + written + "'", dir).exit_code == 2);  // needs repair
  const std::string bad = appell_hamel_with_z(dir, "bad_pin.toml", "[0.0, 0.559]\nfixed = [\"w'\"]");
  const Run located = nhc_run("analyze '" + bad + "'", dir);
  CHECK(located.exit_code == 2);
  CHECK_THAT(located.err, Contains("fixed names 'w''"));
}

namespace {

/// examples/appell_hamel.toml with an [outputs] table appended, written to dir/name.
std::string appell_hamel_with_outputs(const std::string& dir, const std::string& name, const std::string& outputs) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml") << "\n[outputs]\n"
                      << outputs;
  return path;
}

std::string csv_header_line(const std::string& csv) { return csv.substr(0, csv.find('\n')); }

}  // namespace

TEST_CASE("[outputs] are CSV columns in file order, not invariants", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_scene_outputs");
  const std::string scene = appell_hamel_with_outputs(
      dir, "outputs.toml", "speed = \"sqrt(x'^2 + y'^2)\"\nlift = \"2*lambda1\"\nclimb = \"z''\"\nclock = \"a*t\"\n");
  const Run r = nhc_run("simulate '" + scene + "' --output-times 0:0.1:0.2 -o -", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(csv_header_line(r.out) ==
        "t,x,x',x'',y,y',y'',z,z',z'',lambda1,hidden:1,invariant:energy,speed,lift,climb,clock");
  for (int k = 0; k < 3; ++k) {
    INFO("row " << k);
    const std::vector<double> row = csv_row(r.out, k);
    REQUIRE(row.size() == 17);
    const double t = row[0];
    // Chetaev: the horizontal speed falls as v' = −g k/(1 + k²), k = b/a = 1/2 (docs/models.md).
    CHECK(std::abs(row[13] - (std::sqrt(1.25) - 9.81 * 0.5 / 1.25 * t)) < 1e-8);
    CHECK(std::abs(row[13] - std::hypot(row[2], row[5])) < 1e-14);
    CHECK(row[14] == 2 * row[10]);
    CHECK(row[15] == row[9]);  // z'' = k v' = −1.962
    CHECK(std::abs(row[15] + 1.962) < 1e-8);
    CHECK(row[16] == t);
  }
  // -o -: the CSV alone on standard output; the summary, on standard error, lists the outputs
  // and checks none of them for drift.
  CHECK(r.out.find("nhc simulate") == std::string::npos);
  CHECK_THAT(r.err, Contains("  outputs (CSV columns, not checked for drift): speed lift climb clock\n") &&
                        Contains("wrote the CSV to standard output (3 rows)"));
  CHECK(r.err.find("invariant speed") == std::string::npos);
  CHECK(r.err.find("invariant lift") == std::string::npos);

  // --columns picks outputs like any other column.
  const Run columns = nhc_run("simulate '" + scene + "' --columns clock,speed,x -o -", dir);
  REQUIRE(columns.exit_code == 0);
  CHECK(csv_header_line(columns.out) == "t,clock,speed,x");
  const std::vector<double> first = csv_row(columns.out, 0);
  REQUIRE(first.size() == 4);
  CHECK(std::abs(first[2] - std::sqrt(1.25)) < 1e-14);
}

TEST_CASE("bad [outputs] are located errors", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_bad_outputs");
  struct Case {
    std::string outputs, model, message;
  };
  // The [outputs] table starts on line 34 of the written scene; entries follow one per line.
  const std::vector<Case> cases = {
      {"speed = \"sqrt(x'^2 + )\"\n", "chetaev", ":35:22: error: in output 'speed' \"sqrt(x'^2 + )\": unexpected ')'"},
      {"x = \"t\"\n", "chetaev", ":35:1: error: invalid output name 'x': the name is used twice"},
      {"lambda2 = \"t\"\n", "chetaev", ":35:1: error: invalid output name 'lambda2': lambda<N> names are reserved"},
      {"w = \"q\"\n", "chetaev", ":35:6: error: in output 'w' \"q\": unknown name 'q'"},
      {"v = 3\n", "chetaev", ":35:5: error: "},
      {"speed = \"x'\"\nlift = { expression = \"lambda1\", required = true }\n", "suslov",
       ":36:23: error: output 'lift' uses lambda1 (it has no multiplier lambda1), which the suslov model does not "
       "compute"},
      {"jerk = { expression = \"x'''\", required = true }\n", "chetaev",
       ":35:23: error: output 'jerk' uses x''', which the chetaev model does not compute"},
      {"jerk = { expression = \"x'''\", needed = true }\n", "chetaev", ":35:"},
  };
  for (const Case& c : cases) {
    INFO(c.outputs);
    const std::string scene = appell_hamel_with_outputs(dir, "bad.toml", c.outputs);
    const Run r = nhc_run("simulate '" + scene + "' -m " + c.model + " -o '" + dir + "/out.csv'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.rfind(scene + c.message, 0) == 0);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(file_exists(dir + "/out.csv"));
  }
}

TEST_CASE("an output or invariant a model cannot compute is left out of its CSV with a note", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_left_out_outputs");
  // lambda1 is a state of the chetaev model, not of the suslov model (which has no multipliers);
  // lambda1' is computed by neither.
  const std::string scene =
      appell_hamel_with_outputs(dir, "left_out.toml", "speed = \"x'\"\nlift = \"lambda1\"\nlift_rate = \"lambda1'\"\n");
  const Run suslov = nhc_run("simulate '" + scene + "' -m suslov -o '" + dir + "/suslov.csv'", dir);
  REQUIRE(suslov.exit_code == 0);
  CHECK_THAT(suslov.err, Contains("note: output 'lift' is left out of the suslov model's CSV: it uses lambda1 "
                                  "(it has no multiplier lambda1), which the suslov model does not compute\n"));
  CHECK(csv_header_line(read_file(dir + "/suslov.csv")).find("lift") == std::string::npos);
  CHECK(csv_header_line(read_file(dir + "/suslov.csv")).find("speed") != std::string::npos);
  const Run chetaev = nhc_run("simulate '" + scene + "' -m chetaev -o '" + dir + "/chetaev.csv'", dir);
  REQUIRE(chetaev.exit_code == 0);
  CHECK_THAT(chetaev.err,
             Contains("note: output 'lift_rate' is left out of the chetaev model's CSV: it uses lambda1'"));
  CHECK(chetaev.err.find("'lift' is left out") == std::string::npos);
  const std::string csv = read_file(dir + "/chetaev.csv");
  std::vector<std::string> names;
  std::stringstream header(csv_header_line(csv));
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  CHECK(std::count(names.begin(), names.end(), "lift_rate") == 0);
  const auto column = [&](const std::string& n) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
  };
  // The lift column is the multiplier column itself.
  const std::vector<double> row = csv_row(csv, 3);
  REQUIRE(column("lift") < row.size());
  REQUIRE(column("lambda1") < row.size());
  CHECK(row[column("lift")] == row[column("lambda1")]);
}

TEST_CASE("a singular iteration matrix is reported in the scene's words, with the quantity that blew up", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("first_hour_singular_matrix");
  // tests/cli/scenes/vanishing_mass.toml: x' = 1/(1 − t) and lambda1 = 1/(1 − t)², the
  // iteration matrix singular at t = 1.
  const Run r =
      nhc_run("simulate tests/cli/scenes/vanishing_mass.toml --output-times 0:0.25:2 -o '" + dir + "/m.csv'", dir);
  CHECK(r.exit_code == 3);
  std::smatch m;
  REQUIRE(std::regex_search(
      r.err, m,
      std::regex(
          R"(^nhc: error: the iteration matrix of the equations \(dF/dstates \+ cj dF/dstates'\) is singular at t = ([0-9.]+) )"
          R"(\(condition number [0-9.e+]+; the states it does not determine: lambda1 \(-?1\)\): )"
          R"(the equations cannot be solved there for x'', y'', lambda1; lambda1 blew up \(lambda1 ≈ [0-9.]+e\+[0-9]+ at the )"
          R"(last accepted step\))")));
  CHECK(std::abs(std::stod(m[1].str()) - 1) < 1e-6);
  CHECK(r.err.find("dF/dy") == std::string::npos);  // IDA's y, y' are not the scene's
  // The motion up to the failure, against the closed form.
  CHECK_THAT(r.out, Contains("the motion up to the failure"));
  const std::string csv = read_file(dir + "/m.csv");
  CHECK(csv_header_line(csv) == "t,x,x',x'',y,y',y'',lambda1,hidden:1");
  for (int k = 0; k < 4; ++k) {
    const std::vector<double> row = csv_row(csv, k);
    const double t = row[0];
    INFO("t = " << t);
    CHECK(std::abs(row[2] - 1 / (1 - t)) < 1e-6 / (1 - t));
    CHECK(std::abs(row[7] - 1 / ((1 - t) * (1 - t))) < 1e-5 / ((1 - t) * (1 - t)));
  }
}

namespace {

/// `text` written to dir/name.
std::string write_scene(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// The example `file` with its [initial] table replaced by `initial`.
std::string example_with_initial(const std::string& file, const std::string& initial) {
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/examples/" + file);
  const std::size_t begin = text.find("[initial]");
  const std::size_t end = text.find("\n[", begin + 1);
  return text.substr(0, begin) + "[initial]\n" + initial + text.substr(end);
}

/// The column named `name` of a CSV's header.
std::size_t csv_column(const std::string& csv, const std::string& name) {
  std::istringstream header(csv.substr(0, csv.find('\n')));
  std::string field;
  for (std::size_t k = 0; std::getline(header, field, ','); ++k)
    if (field == name) return k;
  FAIL("no column " << name);
  return 0;
}

}  // namespace

TEST_CASE("repairing the initial values keeps the given ones that are consistent, in simulate and analyze alike",
          "[cli]") {
  const std::string dir = nhc::test::scratch_dir("repair_keeps_consistent");
  // Appell–Hamel as shipped: x' = 1, y' = 0.5 given, z' missing. f1 = 0 gives z' = (b/a) sqrt(x'² + y'²)
  // = sqrt(1.25)/2, and the energy m/2 (x'² + y'² + z'²) + m g z = (1.25 + 1.25/4)/2 = 0.78125.
  {
    const Run r = nhc_run("simulate examples/appell_hamel.toml --repair-initial -o -", dir);
    REQUIRE(r.exit_code == 0);
    const std::vector<double> row = csv_row(r.out, 0);
    CHECK(row[csv_column(r.out, "x'")] == 1.0);
    CHECK(row[csv_column(r.out, "y'")] == 0.5);
    CHECK(std::abs(row[csv_column(r.out, "z'")] - std::sqrt(1.25) / 2) < 1e-14);
    CHECK(std::abs(row[csv_column(r.out, "invariant:energy")] - 0.78125) < 1e-14);
    const Run analyze = nhc_run("analyze examples/appell_hamel.toml -m chetaev --repair-initial", dir);
    REQUIRE(analyze.exit_code == 0);
    CHECK_THAT(analyze.out, !Contains("repaired"));
  }
  // The family: scenes with some derivatives missing. Each missing one follows from its constraint
  // (closed form below); every given value stays, and the start is the one without --repair-initial.
  struct Case {
    const char* example;
    const char* initial;
    const char* solved;  ///< the missing value's column
    double expected;     ///< its value from the constraint, by hand
    std::vector<std::pair<const char*, double>> kept;
  };
  const std::vector<Case> cases = {
      // Heisenberg: z' = (x y' − y x')/2 = (1·0.7 − 0)/2.
      {"heisenberg.toml",
       "t0 = 0.0\nx = [1.0, 0.3]\ny = [0.0, 0.7]\nz = [0.0]\n",
       "z'",
       0.35,
       {{"x'", 0.3}, {"y'", 0.7}}},
      // Heisenberg off the origin: z' = (1·0.7 − 2·0.3)/2.
      {"heisenberg.toml",
       "t0 = 0.0\nx = [1.0, 0.3]\ny = [2.0, 0.7]\nz = [0.0]\n",
       "z'",
       0.05,
       {{"x'", 0.3}, {"y'", 0.7}}},
      // Knife edge: x' sin φ = y' cos φ, so y' = x' tan φ, or x' = y' cot φ.
      {"knife_edge.toml",
       "t0 = 0.0\nx = [0.0, 1.0]\ny = [0.0]\nphi = [0.5, 0.2]\n",
       "y'",
       std::tan(0.5),
       {{"x'", 1.0}, {"phi'", 0.2}}},
      {"knife_edge.toml",
       "t0 = 0.0\nx = [0.0]\ny = [0.0, 1.0]\nphi = [0.5, 0.2]\n",
       "x'",
       1 / std::tan(0.5),
       {{"y'", 1.0}, {"phi'", 0.2}}},
  };
  for (const Case& c : cases) {
    INFO(c.example << ": " << c.initial);
    const std::string scene = write_scene(dir, std::string("family_") + c.solved[0] + "_" + c.example,
                                          example_with_initial(c.example, c.initial));
    const Run repaired = nhc_run("simulate '" + scene + "' --repair-initial -o -", dir);
    const Run plain = nhc_run("simulate '" + scene + "' -o -", dir);
    REQUIRE(repaired.exit_code == 0);
    REQUIRE(plain.exit_code == 0);
    const std::vector<double> row = csv_row(repaired.out, 0);
    CHECK(row == csv_row(plain.out, 0));
    CHECK(std::abs(row[csv_column(repaired.out, c.solved)] - c.expected) < 1e-12);
    for (const auto& [name, value] : c.kept) CHECK(row[csv_column(repaired.out, name)] == value);
    const Run analyze = nhc_run("analyze '" + scene + "' --repair-initial", dir);
    CHECK(analyze.exit_code == 0);
    CHECK_THAT(analyze.out, !Contains("repaired"));
  }
}

TEST_CASE("a run to a far t_end starts: the initial point's calculation does not take its scale from t_end", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("far_t_end");
  // x'' = -x: to t_end = 1e7 with one output IDACalcIC took its first step as 1e4 and failed at t0
  // where 1e6 ran. The step limit now stops each run after its start, at a t > 0.
  const std::string scene = write_scene(dir, "ho.toml",
                                        "name = \"ho\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - x^2/2\"\n"
                                        "[initial]\nx = [1.0, 0.0]\n[simulate]\nt_end = 10.0\n");
  for (const char* t_end : {"1e6", "1e7", "1e9", "1e12"}) {
    INFO("--t-end " << t_end);
    const Run r = nhc_run("simulate '" + scene + "' --t-end " + t_end + " --outputs 1 --max-steps 50", dir);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Contains("the step limit (50 steps) was reached at t = 0.") && !Contains("IDACalcIC"));
  }
  // The first steps follow cos t whatever t_end is: 2000 steps reach past t = 1.
  const Run r = nhc_run("simulate '" + scene + "' --output-times 0,1,1e7 --max-steps 2000 -o -", dir);
  CHECK(r.exit_code == 3);
  const std::vector<double> row = csv_row(r.out, 1);
  REQUIRE(row.size() > 1);
  CHECK(row[0] == 1.0);
  CHECK(std::abs(row[1] - std::cos(1.0)) < 1e-6);
}
