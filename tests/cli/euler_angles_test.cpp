// A run that fails where its Euler angles are singular names the angle and its value and points
// to quat() (docs/quaternions.md); one that does not go there says nothing of them. The scenes:
// balls rolling on a turntable, tests/cli/scenes/ball_turntable_zxz.toml (z-x-z angles, th
// reaches pi near t = 0.31) and ball_turntable_zyx.toml (z-y-x, th reaches pi/2 near t = 1.77),
// with both backends.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using Catch::Matchers::Contains;
using nhc::test::read_file;
using nhc::test::Run;

Run nhc_run(const std::string& args, const std::string& dir) {
  return nhc::test::run(std::string("cd '") + NHC_SOURCE_DIR + "' && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                            "/tests/cli/nhc-cache' " + nhc::test::nhc_command() + " " + args,
                        dir);
}

/// The CSV's rows of numbers (the header line skipped).
std::vector<std::vector<double>> csv_rows(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> values;
    std::istringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
    rows.push_back(values);
  }
  return rows;
}

const double pi = std::acos(-1.0);

/// Column `name` of the CSV's header.
std::size_t column(const std::string& csv, const std::string& name) {
  const std::string header = csv.substr(0, csv.find('\n'));
  std::size_t index = 0, from = 0;
  for (std::size_t comma; (comma = header.find(',', from)) != std::string::npos; from = comma + 1, ++index)
    if (header.substr(from, comma - from) == name) return index;
  REQUIRE(header.substr(from) == name);
  return index;
}

/// The ball's centre velocity against the closed form: rolling on a table turning at W, the centre
/// obeys c'' = (2/7) W e_z x c' (J = 2/5 m r^2, W = 1): c' keeps its length and turns at 2/7.
void check_centre_velocity(const std::string& csv) {
  const auto rows = csv_rows(csv);
  REQUIRE(rows.size() > 3);
  const std::size_t xd = column(csv, "x'"), yd = column(csv, "y'");
  const double u0 = rows[0][xd], v0 = rows[0][yd];
  for (const auto& row : rows) {
    const double a = 2.0 / 7.0 * row[0];
    INFO("t = " << row[0]);
    CHECK(std::abs(row[xd] - (u0 * std::cos(a) - v0 * std::sin(a))) < 1e-7);
    CHECK(std::abs(row[yd] - (u0 * std::sin(a) + v0 * std::cos(a))) < 1e-7);
  }
}

/// The words every such error has, after the angle's value.
const std::string kSuggestion =
    R"(there the angular velocity does not determine the rates psi', th', ph'\); write the attitude with )"
    R"(quat\(q0, q1, q2, q3\) and the constraint q0\^2 \+ q1\^2 \+ q2\^2 \+ q3\^2 = 1 instead )"
    R"(\(docs/quaternions.md\)\. The solver: )";

}  // namespace

TEST_CASE("a run through a singularity of z-x-z Euler angles names the angle and suggests quat()", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_zxz");
  for (const std::string backend : {"compiled", "interpreted"}) {
    INFO(backend);
    const std::string csv_path = dir + "/" + backend + ".csv";
    const Run r = nhc_run("simulate tests/cli/scenes/ball_turntable_zxz.toml --backend " + backend +
                              " --output-times 0:0.01:1 -o '" + csv_path + "'",
                          dir);
    CHECK(r.exit_code == 3);
    std::smatch m;
    REQUIRE(std::regex_search(r.err, m,
                              std::regex(R"(nhc: error: the z-x-z Euler angles psi, th, ph are close to their )"
                                         R"(singularity at t = ([0-9.]+): th = ([0-9.]+) \(z-x-z angles are )"
                                         R"(singular at th = 0, pi: )" +
                                         kSuggestion)));
    const double t = std::stod(m[1].str()), th = std::stod(m[2].str());
    CHECK(std::abs(std::sin(th)) < 0.1);
    CHECK(std::abs(th - pi) < 0.1);
    CHECK((t > 0.25 && t < 0.35));
    // Not the symptom: the iteration matrix's null directions were the multipliers.
    CHECK(r.err.find("the states it does not determine") == std::string::npos);
    // The motion up to the failure against the closed form of the centre.
    check_centre_velocity(read_file(csv_path));
  }
  // The run with sensitivities says the same.
  const Run sensitivities = nhc_run(
      "simulate tests/cli/scenes/ball_turntable_zxz.toml --sensitivity W -o '" + dir + "/sensitivities.csv'", dir);
  CHECK(sensitivities.exit_code == 3);
  CHECK_THAT(sensitivities.err,
             Contains("nhc: error: the z-x-z Euler angles psi, th, ph are close to their singularity at t = "));
}

TEST_CASE("a run through a singularity of Tait-Bryan angles names the middle angle at pi/2", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_zyx");
  for (const std::string backend : {"compiled", "interpreted"}) {
    INFO(backend);
    const std::string csv_path = dir + "/" + backend + ".csv";
    const Run r = nhc_run(
        "simulate tests/cli/scenes/ball_turntable_zyx.toml --backend " + backend + " -o '" + csv_path + "'", dir);
    CHECK(r.exit_code == 3);
    std::smatch m;
    REQUIRE(std::regex_search(r.err, m,
                              std::regex(R"(nhc: error: the z-y-x Euler angles psi, th, ph are close to their )"
                                         R"(singularity at t = ([0-9.]+): th = (-?[0-9.]+) \(z-y-x angles are )"
                                         R"(singular at th = -pi/2, pi/2: )" +
                                         kSuggestion)));
    const double t = std::stod(m[1].str()), th = std::stod(m[2].str());
    CHECK(std::abs(std::cos(th)) < 0.1);
    CHECK((t > 1.6 && t < 1.9));
    check_centre_velocity(read_file(csv_path));
  }
}

TEST_CASE("a run with Euler angles that does not reach their singularity says nothing of them", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_elsewhere");
  // Stops before th = pi: a plain run.
  const Run before = nhc_run("simulate tests/cli/scenes/ball_turntable_zxz.toml --t-end 0.2 -o -", dir);
  CHECK(before.exit_code == 0);
  CHECK(before.err.find("Euler") == std::string::npos);
  CHECK(before.err.find("quat(") == std::string::npos);
  // Fails elsewhere: a second body whose mass 1 - 10t vanishes at t = 0.1 (z'' = 10 z'/(1 - 10t)),
  // where th is about 2.7, far from 0 and pi: the failure is told in the solver's words.
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/ball_turntable_zxz.toml");
  text = std::regex_replace(text, std::regex(R"(coordinates = \["x", "y", "psi", "th", "ph"\])"),
                            R"(coordinates = ["x", "y", "psi", "th", "ph", "z"])");
  text = std::regex_replace(text, std::regex(R"(lagrangian = "T")"), R"(lagrangian = "T + (1 - 10*t)*z'^2/2")");
  text = std::regex_replace(text, std::regex(R"(\nph = \[0\.0, 0\.0\])"), "\nph = [0.0, 0.0]\nz = [0.0, 1.0]");
  const std::string scene = dir + "/vanishing.toml";
  std::ofstream(scene) << text;
  const Run elsewhere = nhc_run("simulate '" + scene + "' -o '" + dir + "/vanishing.csv'", dir);
  CHECK(elsewhere.exit_code == 3);
  CHECK_THAT(elsewhere.err, Contains("nhc: error: "));
  CHECK_THAT(elsewhere.err, Contains("t = 0.0999"));
  CHECK(elsewhere.err.find("Euler") == std::string::npos);
  CHECK(elsewhere.err.find("quat(") == std::string::npos);
}

TEST_CASE("a start at a singularity of Euler angles names it in analyze and simulate", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_start");
  // The z-x-z ball started at th = 0 (x', y' from the constraints: w = th' (cos psi, sin psi, 0)).
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/ball_turntable_zxz.toml");
  text = std::regex_replace(text, std::regex(R"(\nx = \[.*\])"), "\nx = [1.0, 0.14776010333066977]");
  text = std::regex_replace(text, std::regex(R"(\ny = \[.*\])"), "\ny = [0.0, 0.522331755437197]");
  text = std::regex_replace(text, std::regex(R"(\nth = \[.*\])"), "\nth = [0.0, 1.0]");
  const std::string scene = dir + "/upright.toml";
  std::ofstream(scene) << text;
  const Run analyze = nhc_run("analyze '" + scene + "' -m chetaev", dir);
  CHECK(analyze.exit_code == 3);
  CHECK_THAT(analyze.err, Contains("nhc: error: the system Jacobian of the chetaev model is singular at t0 = 0"));
  CHECK_THAT(analyze.err, Contains("; the z-x-z Euler angles psi, th, ph are singular there (th = 0), at th = 0, pi, "
                                   "where the angular velocity does not determine the rates: write the attitude "
                                   "with quat(q0, q1, q2, q3)"));
  const Run simulate = nhc_run("simulate '" + scene + "' -o '" + dir + "/upright.csv'", dir);
  CHECK(simulate.exit_code == 3);
  CHECK_THAT(simulate.err, Contains("nhc: error: the z-x-z Euler angles psi, th, ph are close to their singularity "
                                    "at t = "));
}
