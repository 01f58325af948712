// `nhc simulate --input` on the driven oscillator x'' = -x + F from rest
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
      const Run r = run(nhc_command() + " simulate '" + kScene + "' --model " + model + " --input 'F=sin(3*t)' -o '" +
                            dir + "/x.csv'",
                        dir);
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
    const Run r =
        run(nhc_command() + " simulate '" + kScene + "' --input 'F=@" + dir + "/F.csv' -o '" + dir + "/x.csv'", dir);
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
      // F=x+1 is a feedback law (compiled into the equations): python/tests/test_control.py runs
      // laws from --input and refuses a law of an acceleration.
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

TEST_CASE("nhc connect refuses a scene with inputs, --sensitivity one with --input, in words", "[cli][inputs]") {
  // Sensitivities follow the default signals (python/tests/test_control.py checks them against
  // finite differences); an --input replacing a signal has no known derivative by the parameters.
  const std::string dir = scratch_dir("input_refusals");
  const Run connect = run(nhc_command() + " connect '" + kScene + "' --to x=1 --t-end 1 -o '" + dir + "/x.csv'", dir);
  CHECK(connect.exit_code == 2);
  CHECK(connect.err.find("driven_oscillator.toml:7:1: error:") != std::string::npos);
  CHECK(connect.err.find("of a scene with [inputs] (F) are not supported") != std::string::npos);
  const Run replaced =
      run(nhc_command() + " simulate '" + kScene + "' --sensitivity 'x(0)' --input F=0 -o '" + dir + "/x.csv'", dir);
  CHECK(replaced.exit_code == 2);
  CHECK(replaced.err.find("--sensitivity follows the scene's default input signals") != std::string::npos);
  CHECK_FALSE(file_exists(dir + "/x.csv"));
  const Run followed =
      run(nhc_command() + " simulate '" + kScene + "' --sensitivity 'x(0)' -o '" + dir + "/x.csv'", dir);
  CHECK(followed.exit_code == 0);
  CHECK(file_exists(dir + "/x.csv"));
}

namespace {

/// Column `name` of a CSV.
std::vector<double> csv_column(const std::string& csv, const std::string& name) {
  std::istringstream in(csv);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  int index = -1;
  for (int k = 0; std::getline(header, cell, ','); ++k)
    if (cell == name) index = k;
  REQUIRE(index >= 0);
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    for (int k = 0; std::getline(cells, cell, ','); ++k)
      if (k == index) values.push_back(std::stod(cell));
  }
  return values;
}

/// The numbers of the JSON array that follows `"key":` after `from` in a page.
std::vector<double> array_after(const std::string& page, const std::string& key, std::size_t from = 0) {
  const std::size_t at = page.find("\"" + key + "\":[", from);
  REQUIRE(at != std::string::npos);
  const std::size_t open = page.find('[', at), close = page.find(']', open);
  std::vector<double> values;
  std::stringstream cells(page.substr(open + 1, close - open - 1));
  std::string cell;
  while (std::getline(cells, cell, ',')) values.push_back(std::stod(cell));
  return values;
}

}  // namespace

TEST_CASE("[outputs] and [visual] read the inputs as the run drives them", "[cli][inputs]") {
  const std::string dir = scratch_dir("input_in_outputs");
  // The driven oscillator with a time-varying default F = sin(2t)/2, an output 2F and a sphere at (x, F, 0).
  std::string text = read_file(kScene);
  text.replace(text.find("F = \"0\""), 7, "F = \"0.5*sin(2*t)\"");
  text += "[outputs]\nuu = \"2*F\"\n[visual]\nb = { shape = \"sphere\", radius = \"0.1\", center = \"[x, F, 0]\" }\n";
  const std::string scene = dir + "/driven.toml";
  std::ofstream(scene) << text;
  {
    std::ofstream series(dir + "/F.csv");
    series.precision(17);
    series << "t,F\n";
    for (int k = 0; k <= 300; ++k) series << k * 1e-2 << "," << std::cos(k * 1e-2) << "\n";
  }
  struct Case {
    std::string flag;
    double (*F)(double t);  ///< the signal, by hand (the CSV's between its knots: within 1.25e-5)
  };
  const std::vector<Case> cases = {
      {"", [](double t) { return 0.5 * std::sin(2 * t); }},
      {"--input F=0.7", [](double) { return 0.7; }},
      {"--input 'F=sin(3*t)'", [](double t) { return std::sin(3 * t); }},
      {"--input 'F=@" + dir + "/F.csv'", [](double t) { return std::cos(t); }},
  };
  for (const Case& c : cases) {
    INFO(c.flag);
    const Run r = run(nhc_command() + " simulate '" + scene + "' " + c.flag + " --outputs 37 -o -", dir);
    REQUIRE(r.exit_code == 0);
    const std::vector<double> t = csv_column(r.out, "t"), F = csv_column(r.out, "input:F"),
                              uu = csv_column(r.out, "uu");
    REQUIRE(uu.size() == 38);
    for (std::size_t k = 0; k < uu.size(); ++k) {
      CHECK(uu[k] == 2 * F[k]);
      CHECK(std::abs(F[k] - c.F(t[k])) < 2e-5);
    }
  }
  const Run page =
      run(nhc_command() + " animate '" + scene + "' --input 'F=sin(3*t)' --outputs 37 -o '" + dir + "/page'", dir);
  REQUIRE(page.exit_code == 0);
  const std::string html = read_file(dir + "/page/index.html");
  const std::vector<double> t = array_after(html, "t");
  const std::vector<double> centre = array_after(html, "position", html.find("\"name\":\"b\""));
  REQUIRE(t.size() == 38);
  REQUIRE(centre.size() == 3 * 38);
  for (std::size_t k = 0; k < t.size(); ++k) {
    CHECK(std::isfinite(centre[3 * k]));
    // The page keeps 9 significant digits of t and of F: 3 · 5e-9 + 5e-10 at most.
    CHECK(std::abs(centre[3 * k + 1] - std::sin(3 * t[k])) < 2e-8);
  }
}

TEST_CASE("a feedback law's input:NAME column holds the value the law applies", "[cli][inputs]") {
  // A law is compiled into the equations in place of its input (docs/scenes.md, "Feedback laws");
  // its column holds the law at each row's own state, not the input's default signal 0.
  const std::string dir = scratch_dir("law_columns");
  const std::string pendulum = std::string(NHC_SOURCE_DIR) + "/examples/wheeled_pendulum.toml";
  std::string text = read_file(pendulum);
  text.replace(text.find("[definitions]\n"), 14, "[definitions]\ntilt = \"11*th + 2.4*th'\"\n");
  text.replace(text.find("TR = \"0\""), 8, "TR = \"tilt - 0.01*phL'\"");
  const std::string scene = dir + "/closed.toml";
  std::ofstream(scene) << text;
  struct Case {
    std::string command, column;
    double (*law)(const std::string& csv, std::size_t row);
  };
  const std::vector<Case> cases = {
      {" simulate '" + pendulum + "' --input 'TL=-10*th'", "input:TL",
       [](const std::string& csv, std::size_t k) { return -10 * csv_column(csv, "th")[k]; }},
      {" simulate '" + scene + "'", "input:TR",
       [](const std::string& csv, std::size_t k) {
         return 11 * csv_column(csv, "th")[k] + 2.4 * csv_column(csv, "th'")[k] - 0.01 * csv_column(csv, "phL'")[k];
       }},
      {" simulate '" + scene + "' --input 'TL=th*phR + 1'", "input:TL",
       [](const std::string& csv, std::size_t k) { return csv_column(csv, "th")[k] * csv_column(csv, "phR")[k] + 1; }},
      {" simulate '" + pendulum + "' --input 'TL=-10*th' --sensitivity l", "input:TL",
       [](const std::string& csv, std::size_t k) { return -10 * csv_column(csv, "th")[k]; }},
      {" simulate '" + scene + "' --integrator variational --step 0.01", "input:TR",
       [](const std::string& csv, std::size_t k) {
         return 11 * csv_column(csv, "th")[k] + 2.4 * csv_column(csv, "th'")[k] - 0.01 * csv_column(csv, "phL'")[k];
       }},
  };
  for (const Case& c : cases) {
    INFO(c.command);
    const Run r = run(nhc_command() + c.command + " --t-end 0.5 --outputs 20 -o -", dir);
    REQUIRE(r.exit_code == 0);
    const std::vector<double> u = csv_column(r.out, c.column);
    REQUIRE(u.size() == 21);
    double largest = 0;
    for (std::size_t k = 0; k < u.size(); ++k) {
      const double law = c.law(r.out, k);
      CHECK(std::abs(u[k] - law) <= 1e-12 * (1 + std::abs(law)));
      largest = std::max(largest, std::abs(law));
    }
    CHECK(largest > 0.01);  // the law moved: a column of zeros would not pass
  }
}
