// [ensemble]: the design generators on their own, and `nhc ensemble` end to end: the
// Appell–Hamel stop-time map against its closed form t* = v0 (1 + k^2)/(g k) (docs/ensemble.md),
// a failing run recorded without stopping the ensemble, --resume, --plot, and bad input (exit 2,
// the flag named, no FILE.h5 left). Result files are read with the plain HDF5 C API.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "command_runner.hpp"
#include "nhc/ensemble/design.hpp"
#include "nhc/errors.hpp"

namespace {

using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::run;
using nhc::test::scratch_dir;
namespace ens = nhc::ensemble;

const std::string kStopScene = std::string(NHC_SOURCE_DIR) + "/examples/ensemble/appell_hamel_stop.toml";

std::string ensemble(const std::string& args) {
  return "NHC_CACHE_DIR='" + std::string(NHC_BINARY_DIR) + "/tests/scratch/ensemble-cache' " + nhc_command() +
         " ensemble '" + kStopScene + "' " + args;
}

/// A whole dataset as doubles (or int8 outcomes as their codes), read with the HDF5 C API.
std::vector<double> read_doubles(const std::string& file, const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t d = H5Dopen2(f, path.c_str(), H5P_DEFAULT);
  REQUIRE(d >= 0);
  const hid_t space = H5Dget_space(d);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  REQUIRE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return v;
}

std::vector<int> read_outcomes(const std::string& file) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t d = H5Dopen2(f, "/runs/outcome", H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  std::vector<signed char> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  // The file type is an enum over int8; read its integer codes.
  REQUIRE(H5Dread(d, H5T_NATIVE_SCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return std::vector<int>(v.begin(), v.end());
}

}  // namespace

TEST_CASE("a grid is the Cartesian product, the last variable fastest", "[ensemble]") {
  const ens::Design d = ens::make_grid({ens::parse_vary("a=0:1:3"), ens::parse_vary("x'(0)=10:20:2")});
  REQUIRE(d.runs == 6);
  const std::vector<double> expected{0, 10, 0, 20, 0.5, 10, 0.5, 20, 1, 10, 1, 20};
  CHECK(d.values == expected);
  CHECK(d.grid_shape == std::vector<long>{3, 2});
  CHECK(ens::grid_values(ens::parse_vary("b=2:2:1")) == std::vector<double>{2});
}

TEST_CASE("random samples depend on the seed and the run only", "[ensemble]") {
  const auto u = ens::parse_sample("b=uniform(1,3)"), n = ens::parse_sample("v=normal(2, 0.5)");
  const ens::Design small = ens::make_sample({u, n}, 10, 42), large = ens::make_sample({u, n}, 20000, 42);
  // The first runs of a larger sample are the smaller sample (so are the samples of any rank).
  CHECK(std::equal(small.values.begin(), small.values.end(), large.values.begin()));
  CHECK(ens::make_sample({u, n}, 10, 43).values != small.values);
  // The laws: mean and deviation within 4 standard errors.
  double su = 0, sn = 0, sn2 = 0;
  bool in_range = true;
  for (long k = 0; k < large.runs; ++k) {
    const double b = large.row(k)[0], v = large.row(k)[1];
    in_range = in_range && b > 1 && b < 3;
    su += b;
    sn += v;
    sn2 += v * v;
  }
  const double N = static_cast<double>(large.runs);
  CHECK(in_range);
  CHECK(std::abs(su / N - 2.0) < 4 * (2 / std::sqrt(12.0)) / std::sqrt(N));
  CHECK(std::abs(sn / N - 2.0) < 4 * 0.5 / std::sqrt(N));
  CHECK(std::abs(std::sqrt(sn2 / N - (sn / N) * (sn / N)) - 0.5) < 4 * 0.5 / std::sqrt(2 * N));
}

TEST_CASE("malformed --vary and --sample are refused with the flag named", "[ensemble]") {
  for (const char* bad : {"b", "b=1:2", "b=1:2:0", "b=1:1:3", "b=x:2:3", "b=1:2:2.5", "=1:2:3", "b=1:2:-4"})
    CHECK_THROWS_AS(ens::parse_vary(bad), nhc::InputError);
  for (const char* bad : {"b=uniform(2,1)", "b=uniform(1,1)", "b=normal(0,0)", "b=gamma(1,2)", "b=uniform(1)"})
    CHECK_THROWS_AS(ens::parse_sample(bad), nhc::InputError);
  CHECK_THROWS_WITH(ens::parse_vary("b=1:1:3"), Catch::Contains("--vary b=1:1:3") && Catch::Contains("empty"));
  CHECK_THROWS_AS(ens::make_grid({ens::parse_vary("b=0:1:2"), ens::parse_vary("b=0:1:3")}), nhc::InputError);
}

TEST_CASE("Appell–Hamel stop times on a grid of v0 and b/a match t* = v0 (1 + k^2)/(g k)", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_stop_map");
  const std::string file = dir + "/stop.h5";
  const auto r = run(ensemble("--vary \"x'(0)=0.5:2:7\" --vary b=0.2:2:6 --plot t_stop -o '" + file + "'"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<double> design = read_doubles(file, "/design/values"), t_stop = read_doubles(file, "/runs/t_stop");
  const std::vector<int> outcome = read_outcomes(file);
  REQUIRE(t_stop.size() == 42);
  REQUIRE(design.size() == 2 * 42);
  const double g = 9.81;  // the scene's; a = 1, so b is b/a
  for (std::size_t k = 0; k < t_stop.size(); ++k) {
    const double v0 = design[2 * k], ratio = design[2 * k + 1];
    const double t_star = v0 * (1 + ratio * ratio) / (g * ratio);
    // The run stops where the singular-set monitor x'^2 + y'^2 = v^2 falls below 1e-14 of its
    // start (IntegratorOptions::singularity_threshold), i.e. at v = 1e-7 v0: t* (1 - 1e-7),
    // since v falls linearly (docs/ensemble.md).
    const double t_monitor = t_star * (1 - std::sqrt(1e-14));
    INFO("v0 = " << v0 << ", b/a = " << ratio << ", t* = " << t_star << ", t_stop = " << t_stop[k]);
    CHECK(outcome[k] == 2);  // stopped at the singular point
    CHECK(std::abs(t_stop[k] - t_monitor) < 1e-10 * t_star);
  }
  CHECK(file_exists(dir + "/stop_t_stop.svg"));
  CHECK(file_exists(dir + "/stop_t_stop.png"));

  // nhc plot redraws any outcome from the file; an outcome the file lacks is bad input.
  const auto plot = run(nhc_command() + " plot '" + file + "' \"final:x'\" -o '" + dir + "/vx'", dir);
  INFO(plot.err);
  CHECK(plot.exit_code == 0);
  CHECK(file_exists(dir + "/vx.svg"));
  const auto unknown = run(nhc_command() + " plot '" + file + "' drift:momentum -o '" + dir + "/m'", dir);
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.err.find("OUTCOME drift:momentum: error: unknown outcome; this ensemble has t_stop") !=
        std::string::npos);
  CHECK_FALSE(file_exists(dir + "/m.svg"));
}

TEST_CASE("ensemble runs start from --initial: stop times from x'(0) = 1.5 and t0 = 0.25", "[ensemble]") {
  // The Appell–Hamel stop time t* = v0 (1 + k^2)/(g k) after t0, with v0 and t0 given from outside
  // the scene (whose [initial] has x'(0) = 1, t0 = 0).
  const std::string dir = scratch_dir("ensemble_initial");
  const std::string file = dir + "/stop.h5";
  const std::string args = "--vary b=0.5:1:2 --initial \"x'=1.5\" --initial t0=0.25 ";
  const auto r = run(ensemble(args + "-o '" + file + "'"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<double> design = read_doubles(file, "/design/values"), t_stop = read_doubles(file, "/runs/t_stop");
  REQUIRE(t_stop.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    const double ratio = design[k], t_star = 1.5 * (1 + ratio * ratio) / (9.81 * ratio);
    INFO("b/a = " << ratio << ", t_stop = " << t_stop[k]);
    CHECK(std::abs(t_stop[k] - (0.25 + t_star * (1 - std::sqrt(1e-14)))) < 1e-9);
  }
  // Runs from other initial values are another ensemble: not resumed.
  const auto other = run(ensemble("--vary b=0.5:1:2 --resume -o '" + file + "'"), dir);
  CHECK(other.exit_code == 2);
  CHECK(other.err.find("its --initial values differ") != std::string::npos);
}

TEST_CASE("a 1-D grid is drawn as a line", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_line");
  const auto r = run(ensemble("--vary b=0.2:2:9 --plot drift:energy -o '" + dir + "/line.h5'"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(nhc::test::read_file(dir + "/line_drift_energy.gp").find("with linespoints") != std::string::npos);
  CHECK(file_exists(dir + "/line_drift_energy.svg"));
}

TEST_CASE("a failing run is recorded and the ensemble goes on", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_failure");
  const std::string file = dir + "/m.h5";
  // m = 0 makes the iteration matrix singular; the runs beside it integrate to t_end.
  const auto r = run(ensemble("--vary m=-1:1:5 --t-end 0.05 -o '" + file + "'"), dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<int> outcome = read_outcomes(file);
  REQUIRE(outcome.size() == 5);
  CHECK(outcome[2] == 3);                                                 // failed
  for (int k : {3, 4}) CHECK(outcome[static_cast<std::size_t>(k)] == 1);  // ok
  CHECK(r.out.find("1 failed") != std::string::npos);
}

TEST_CASE("resuming runs only the runs a checkpoint lacks and gives the same file", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_resume");
  const std::string full = dir + "/full.h5", part = dir + "/part.h5";
  const std::string args = "--vary \"x'(0)=0.5:2:4\" --vary b=0.5:1:3 --keep trajectories --outputs 10 ";
  REQUIRE(run(ensemble(args + "-o '" + full + "'"), dir).exit_code == 0);
  REQUIRE(run("cp '" + full + "' '" + part + "'", dir).exit_code == 0);
  {  // A killed ensemble's checkpoint: runs 0, 3, 6, 9 not finished.
    const hid_t f = H5Fopen(part.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/runs/outcome", H5P_DEFAULT);
    const hid_t type = H5Dget_type(d);  // the enum over int8: its codes, written raw
    std::vector<signed char> outcome(12);
    REQUIRE(H5Tget_size(type) == 1);
    REQUIRE(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, outcome.data()) >= 0);
    for (std::size_t k = 0; k < 12; k += 3) outcome[k] = 0;
    REQUIRE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, outcome.data()) >= 0);
    H5Tclose(type);
    H5Dclose(d);
    H5Fclose(f);
  }
  const auto resumed = run(ensemble(args + "--resume -o '" + part + "'"), dir);
  INFO(resumed.err);
  REQUIRE(resumed.exit_code == 0);
  CHECK(resumed.out.find("ran 4 (8 finished before)") != std::string::npos);
  const auto same = run(std::string("'") + NHC_H5_SAME + "' '" + full + "' '" + part +
                            "' --ignore /runs/seconds --ignore /runs/rank --ignore /@ranks --ignore /@threads "
                            "--ignore /@wall_seconds",
                        dir);
  INFO(same.out);
  CHECK(same.exit_code == 0);
  // A different ensemble in FILE.h5 is not resumed.
  const auto other = run(ensemble("--vary b=0.5:1:3 --resume -o '" + part + "'"), dir);
  CHECK(other.exit_code == 2);
  CHECK(other.err.find("--resume") != std::string::npos);
  // Nor the same design over a scene edited under the same name: what the
  // runs were computed from is compared, by the SHA-256 of the scene's text.
  std::ifstream in(kStopScene);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("lagrangian = \"");
  REQUIRE(at != std::string::npos);
  text.insert(at + 14, "2*(");
  text.insert(text.find('"', at + 17), ")");
  std::ofstream(dir + "/edited.toml") << text;
  const auto edited =
      run("NHC_CACHE_DIR='" + std::string(NHC_BINARY_DIR) + "/tests/scratch/ensemble-cache' " + nhc_command() +
              " ensemble '" + dir + "/edited.toml' " + args + "--resume -o '" + part + "'",
          dir);
  INFO(edited.err);
  CHECK(edited.exit_code == 2);
  CHECK(edited.err.find("the scene's text or its --initial values differ from those its runs were computed from") !=
        std::string::npos);
}

TEST_CASE("bad input: exit 2, the flag named, no FILE.h5", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_bad_input");
  const std::string file = dir + "/out.h5";
  struct Case {
    std::string args, words;
  };
  const std::vector<Case> cases{
      {"--vary q=0:1:3", "--vary q=0:1:3: error: unknown name 'q'"},
      {"--vary \"z''(0)=0:1:3\"", "unknown name"},
      {"--vary b=1:1:3", "--vary b=1:1:3: error: the range 1:1 is empty"},
      {"--vary b=0:1:0", "--vary b=0:1:0: error: n = 0 must be at least 1"},
      {"--sample \"b=uniform(2,1)\" --samples 5", "--sample b=uniform(2,1): error: the range (2, 1) is empty"},
      {"--sample \"b=uniform(0,1)\" --samples 0", "--samples 0: error: N must be at least 1"},
      {"--vary b=0:1:3 --keep everything", "--keep everything: error"},
      {"--vary b=0:1:3 --plot final:w", "--plot final:w: error: unknown outcome"},
      {"", "--vary: error"},
  };
  for (const Case& c : cases) {
    const auto r = run(ensemble(c.args + " -o '" + file + "'"), dir);
    INFO(c.args << "\n" << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(c.words) != std::string::npos);
    CHECK_FALSE(file_exists(file));
  }
  // An output under a regular file is bad input (exit 2), as for every output of nhc
  // (nhc/io/output_path.hpp), found before any run; a missing directory is created, as elsewhere.
  run("echo x > '" + dir + "/plain'", dir);
  const auto unwritable = run(ensemble("--vary b=0:1:3 -o '" + dir + "/plain/out.h5'"), dir);
  CHECK(unwritable.exit_code == 2);
  CHECK(unwritable.err.find(dir + "/plain is a file, not a directory, so the output " + dir +
                            "/plain/out.h5 cannot be created under it") != std::string::npos);
  CHECK(unwritable.err.find("ran ") == std::string::npos);
  const auto nested = run(ensemble("--vary b=0:1:3 -o '" + dir + "/new/deeper/out.h5'"), dir);
  CHECK(nested.exit_code == 0);
  CHECK(file_exists(dir + "/new/deeper/out.h5"));
  const auto listing = run(std::string("ls -a '") + dir + "'", dir);
  CHECK(listing.out.find(".tmp") == std::string::npos);
}

TEST_CASE("an interrupted ensemble leaves its last checkpoint and no temporary file", "[ensemble]") {
  const std::string dir = scratch_dir("ensemble_interrupt");
  const std::string file = dir + "/big.h5";
  // The model compiled before (the compile cache), so that runs start at once.
  REQUIRE(run(ensemble("--vary b=0.2:2:2 -o '" + dir + "/warm.h5'"), dir).exit_code == 0);
  // 2 x 10^4 runs of about a millisecond: interrupted after 1.5 s, with checkpoints every 0.2 s.
  const auto r = run("bash -c \"" +
                         ensemble("--vary \\\"x'(0)=0.5:2:200\\\" --vary b=0.2:2:100 --threads 1 "
                                  "--checkpoint-every 0.2 -o '" +
                                  file + "'") +
                         " & pid=\\$!; sleep 1.5; kill -TERM \\$pid; wait \\$pid; echo exit \\$?\"",
                     dir);
  INFO(r.out << r.err);
  REQUIRE(r.out.find("exit 143") != std::string::npos);
  REQUIRE(file_exists(file));
  const std::vector<int> outcome = read_outcomes(file);
  REQUIRE(outcome.size() == 20000);
  const long pending = std::count(outcome.begin(), outcome.end(), 0);
  const long stopped = std::count(outcome.begin(), outcome.end(), 2);
  CHECK(pending > 0);
  CHECK(stopped > 0);
  CHECK(pending + stopped == 20000);
  const auto listing = run(std::string("ls -a '") + dir + "'", dir);
  CHECK(listing.out.find(".tmp") == std::string::npos);
}

TEST_CASE("an ensemble varies a parameter that only [initial] uses: x(0) = A, x(1) = A cos 1", "[ensemble]") {
  // x'' = -x from x = A at rest: x = A cos t. The model's equations do not contain A; each run
  // starts from [initial] evaluated at its own A (before, --vary A was refused: "varying it would
  // change nothing").
  const std::string dir = scratch_dir("ensemble_initial_parameter");
  const std::string scene = dir + "/start.toml", file = dir + "/start.h5";
  std::ofstream(scene) << "name = \"start\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - x^2/2\"\n"
                          "[parameters]\nA = 0.7\n[initial]\nx = [\"A\", 0.0]\n"
                          "[simulate]\nt_end = 1.0\nrtol = 1e-10\natol = 1e-12\n";
  const auto r = run("NHC_CACHE_DIR='" + std::string(NHC_BINARY_DIR) + "/tests/scratch/ensemble-cache' " +
                         nhc_command() + " ensemble '" + scene + "' --vary A=0.5:1.5:3 -o '" + file + "'",
                     dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::vector<double> design = read_doubles(file, "/design/values"),
                            final_state = read_doubles(file, "/runs/final_state");
  REQUIRE(design.size() == 3);
  const std::size_t n = final_state.size() / 3;  // x first among the states
  for (std::size_t k = 0; k < 3; ++k) CHECK(std::abs(final_state[k * n] - design[k] * std::cos(1.0)) < 1e-8);
}
