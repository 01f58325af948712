// `nhc simulate --input` (issue 28) on the driven oscillator x'' = -x + F from rest
// (tests/cli/scenes/driven_oscillator.toml), against the closed form for F = sin(w t):
// x = (w sin t - sin(w t)) / (w^2 - 1). An expression replaces the default F = 0; a CSV series of
// the same signal is interpolated linearly (error O(h^2)); bad flags and files are exit 2 with
// the flag or FILE:LINE:COLUMN, and no CSV is written.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::run;
using nhc::test::Run;
using nhc::test::scratch_dir;

const std::string kScene = std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/driven_oscillator.toml";

/// The largest |x - closed form| over the CSV's rows, and the largest |F column - sin(w t)|.
std::pair<double, double> errors(const std::string& csv, double w) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "t,x,x',x'',input:F");
  double worst_x = 0, worst_F = 0;
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) v.push_back(std::stod(cell));
    REQUIRE(v.size() == 5);
    const double t = v[0];
    worst_x = std::max(worst_x, std::abs(v[1] - (w * std::sin(t) - std::sin(w * t)) / (w * w - 1)));
    worst_F = std::max(worst_F, std::abs(v[4] - std::sin(w * t)));
    ++rows;
  }
  REQUIRE(rows == 201);
  return {worst_x, worst_F};
}

}  // namespace

TEST_CASE("nhc simulate --input: an expression of t and a CSV series replace the default signal", "[cli][inputs]") {
  const std::string dir = scratch_dir("input_flag");
  SECTION("an expression") {
    const Run r = run(nhc_command() + " simulate '" + kScene + "' --input 'F=sin(3*t)' -o '" + dir + "/x.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto [x, F] = errors(read_file(dir + "/x.csv"), 3.0);
    CHECK(x < 1e-8);
    CHECK(F < 1e-15);
  }
  SECTION("every model takes the input (the forcing enters each residual undifferentiated)") {
    for (const std::string model : {"vakonomic", "chetaev", "holder", "suslov"}) {
      INFO("model " << model);
      const Run r = run(nhc_command() + " simulate '" + kScene + "' --model " + model +
                            " --input 'F=sin(3*t)' -o '" + dir + "/x.csv'", dir);
      REQUIRE(r.exit_code == 0);
      CHECK(errors(read_file(dir + "/x.csv"), 3.0).first < 1e-8);
    }
  }
  SECTION("a CSV series, step 1e-3") {
    {
      std::ofstream series(dir + "/F.csv");
      series.precision(17);
      series << "time_note,t,F\n";
      for (int k = 0; k <= 3000; ++k) series << "x," << k * 1e-3 << "," << std::sin(2 * k * 1e-3) << "\n";
    }
    const Run r = run(nhc_command() + " simulate '" + kScene + "' --input 'F=@" + dir + "/F.csv' -o '" + dir +
                          "/x.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto [x, F] = errors(read_file(dir + "/x.csv"), 2.0);
    // Linear interpolation of sin(2t) at h = 1e-3: |F error| <= h^2/8 * 4 = 5e-7, and x follows.
    CHECK(F <= 5e-7);
    CHECK(x <= 1e-6);
    CHECK(x > 1e-9);  // the interpolation shows: the series is what drove the run
  }
}

TEST_CASE("nhc simulate --input: bad flags and series are refused at the flag or the file's line", "[cli][inputs]") {
  const std::string dir = scratch_dir("input_flag_bad");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"G=1", "--input: error: unknown input 'G' (inputs: F)"},
      {"F=x+1", "--input: error: in F=x+1 at character 1: coordinate 'x' is not allowed here"},
      {"F", "--input"},
      {"F=@" + dir + "/missing.csv", "missing.csv: error: cannot read a CSV file for input 'F': No such file"},
      {"F=@" + write("no_column.csv", "t,G\n0,1\n5,2\n"), "no_column.csv:1:1: error: no column 'F'"},
      {"F=@" + write("not_increasing.csv", "t,F\n0,1\n0,2\n"), "not_increasing.csv:3:1: error: times must increase"},
      {"F=@" + write("not_finite.csv", "t,F\n0,1\n1,nan\n"), "not_finite.csv:3:3: error: 'nan' is not a finite number"},
      {"F=@" + write("short.csv", "t,F\n0,1\n1,2\n"), "short.csv:2:1: error: the series covers t from 0 to 1"},
  };
  for (const auto& [flag, message] : cases) {
    INFO("--input " << flag);
    const Run r = run(nhc_command() + " simulate '" + kScene + "' --input '" + flag + "' -o '" + dir + "/x.csv'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(message) != std::string::npos);
    CHECK(r.out.empty());
    CHECK_FALSE(file_exists(dir + "/x.csv"));
  }
}

TEST_CASE("nhc simulate --sensitivity and nhc connect refuse a scene with inputs in words", "[cli][inputs]") {
  const std::string dir = scratch_dir("input_refusals");
  for (const std::string& command : {std::string(" simulate '") + kScene + "' --sensitivity 'x(0)' -o '" + dir + "/x.csv'",
                                     std::string(" connect '") + kScene + "' --to x=1 --t-end 1 -o '" + dir + "/x.csv'"}) {
    INFO(command);
    const Run r = run(nhc_command() + command, dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("driven_oscillator.toml:7:1: error:") != std::string::npos);
    CHECK(r.err.find("of a scene with [inputs] (F) are not supported") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/x.csv"));
  }
}
