// A run that fails where its Euler angles are singular names the angle and its value and points
// to quat() (docs/quaternions.md); one that does not go there says nothing of them. The scenes:
// tests/cli/scenes/euler_angles_tumbling.toml (z-x-z, th = 0.5 + 2t reaches pi at t = 1.3208)
// and tait_bryan_tumbling.toml (z-y-x, th = 2t reaches pi/2 at t = 0.7854), with both backends.
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

}  // namespace

TEST_CASE("a run through a singularity of z-x-z Euler angles names the angle and suggests quat()", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_zxz");
  for (const std::string backend : {"compiled", "interpreted"}) {
    INFO(backend);
    const Run r = nhc_run("simulate tests/cli/scenes/euler_angles_tumbling.toml --backend " + backend +
                              " --output-times 0:0.05:3 -o '" + dir + "/" + backend + ".csv'",
                          dir);
    CHECK(r.exit_code == 3);
    std::smatch m;
    REQUIRE(std::regex_search(
        r.err, m,
        std::regex(R"(nhc: error: the z-x-z Euler angles psi, th, ph are singular at t = ([0-9.]+): th = ([0-9.]+) )"
                   R"(\(z-x-z angles are singular at th = 0, pi: there the angular velocity does not determine the )"
                   R"(rates psi', th', ph'\); write the attitude with quat\(q0, q1, q2, q3\) and the constraint )"
                   R"(q0\^2 \+ q1\^2 \+ q2\^2 \+ q3\^2 = 1 instead \(docs/quaternions.md\)\. The solver: )")));
    // th = 0.5 + 2t reaches pi at t = (pi - 0.5)/2; the run stops within sin(th) < 1e-2 of it.
    const double t = std::stod(m[1].str()), th = std::stod(m[2].str());
    CHECK(std::abs(std::sin(th)) < 1e-2);
    CHECK(std::abs(th - pi) < 1e-2);
    CHECK(std::abs(t - (pi - 0.5) / 2) < 1e-2 / 2);
    CHECK(r.err.find("the states it does not determine") == std::string::npos);
    // The motion up to the failure is the closed form.
    const auto rows = csv_rows(read_file(dir + "/" + backend + ".csv"));
    REQUIRE(rows.size() > 20);
    for (const auto& row : rows) CHECK(std::abs(row[4] - (0.5 + 2 * row[0])) < 1e-6);
  }
}

TEST_CASE("a run through a singularity of Tait-Bryan angles names the middle angle at pi/2", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_zyx");
  for (const std::string backend : {"compiled", "interpreted"}) {
    INFO(backend);
    const Run r = nhc_run("simulate tests/cli/scenes/tait_bryan_tumbling.toml --backend " + backend + " -o '" + dir +
                              "/" + backend + ".csv'",
                          dir);
    CHECK(r.exit_code == 3);
    std::smatch m;
    REQUIRE(std::regex_search(
        r.err, m,
        std::regex(R"(nhc: error: the z-y-x Euler angles psi, th, ph are singular at t = ([0-9.]+): th = ([0-9.]+) )"
                   R"(\(z-y-x angles are singular at th = -pi/2, pi/2: .*quat\(q0, q1, q2, q3\))")));
    const double t = std::stod(m[1].str()), th = std::stod(m[2].str());
    CHECK(std::abs(std::cos(th)) < 1e-2);
    CHECK(std::abs(t - pi / 4) < 1e-2 / 2);
  }
}

TEST_CASE("a run with Euler angles that does not reach their singularity says nothing of them", "[cli]") {
  const std::string dir = nhc::test::scratch_dir("euler_angles_elsewhere");
  // Stops before th = pi: a plain run.
  const Run before = nhc_run("simulate tests/cli/scenes/euler_angles_tumbling.toml --t-end 1.2 -o -", dir);
  CHECK(before.exit_code == 0);
  CHECK(before.err.find("Euler") == std::string::npos);
  CHECK(before.err.find("quat") == std::string::npos);
  // Fails elsewhere: a second body whose mass 1 - 2t vanishes at t = 1/2 (x'' = 2x'/(1 - 2t)),
  // where th = 1.5, far from 0 and pi: the failure is the iteration matrix's, in its own words.
  std::string text = read_file(std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/euler_angles_tumbling.toml");
  text = std::regex_replace(text, std::regex(R"(coordinates = \["psi", "th", "ph"\])"),
                            R"(coordinates = ["psi", "th", "ph", "x"])");
  text = std::regex_replace(text, std::regex(R"(lagrangian = "dot\(J\*Om, Om\)/2")"),
                            R"(lagrangian = "dot(J*Om, Om)/2 + (1 - 2*t)*x'^2/2")");
  text = std::regex_replace(text, std::regex(R"(ph = \[0\.0, 0\.0\])"), "ph = [0.0, 0.0]\nx = [0.0, 1.0]");
  const std::string scene = dir + "/vanishing.toml";
  std::ofstream(scene) << text;
  const Run elsewhere = nhc_run("simulate '" + scene + "' -o '" + dir + "/vanishing.csv'", dir);
  CHECK(elsewhere.exit_code == 3);
  CHECK_THAT(elsewhere.err, Contains("nhc: error: the iteration matrix of the equations"));
  CHECK(elsewhere.err.find("Euler") == std::string::npos);
  CHECK(elsewhere.err.find("quat") == std::string::npos);
}
