// The vakonomic cross-check: with the Lagrangian as the objective and no inputs,
// nhc optimize (collocation, IPOPT) and nhc connect (shooting on the vakonomic equations, IDA)
// solve the same two-point problem by independent methods; their paths agree.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "command_runner.hpp"
#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/scene/scene.hpp"

using namespace nhc;

namespace {

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    REQUIRE(it != header.end());
    return static_cast<std::size_t>(it - header.begin());
  }
  /// Column `name` at time t, linearly interpolated (the rows are 1/2000 of the horizon apart).
  double at(double t, const std::string& name) const {
    const std::size_t c = column(name);
    std::size_t i = 1;
    while (i + 1 < rows.size() && rows[i][0] < t) ++i;
    const double s = (t - rows[i - 1][0]) / (rows[i][0] - rows[i - 1][0]);
    return rows[i - 1][c] + s * (rows[i][c] - rows[i - 1][c]);
  }
};

Table read_table(const std::string& path) {
  std::ifstream in(path);
  Table table;
  std::string line, cell;
  std::getline(in, line);
  for (std::istringstream cells(line); std::getline(cells, cell, ',');) table.header.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (std::istringstream cells(line); std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    table.rows.push_back(row);
  }
  return table;
}

/// The scene `head` with an [optimize] table from the origin to `target` at T = 1, solved on 60
/// intervals, against `nhc connect --to target` on the same scene; the largest difference of
/// the coordinates at the collocation points.
double largest_difference(const std::string& name, const std::string& head, const std::vector<std::string>& coordinates,
                          const std::vector<double>& target) {
  std::string text = head + "\n[optimize]\nt_end = 1.0\n[optimize.initial]\n";
  for (const std::string& q : coordinates) text += q + " = 0.0\n";
  text += "[optimize.final]\n";
  std::string to;
  for (std::size_t i = 0; i < coordinates.size(); ++i) {
    text += fmt::format("{} = {}\n", coordinates[i], target[i]);
    to += fmt::format("{}{}={}", i ? "," : "", coordinates[i], target[i]);
  }
  const std::string dir = test::scratch_dir("optimize_" + name);
  const std::string scene_path = dir + "/" + name + ".toml";
  std::ofstream(scene_path) << text;
  const test::Run shot = test::run(test::nhc_command() + " connect " + scene_path + " --to " + to +
                                       " --t-end 1 --outputs 2000 -o " + dir + "/connect.csv",
                                   dir);
  INFO(shot.out << shot.err);
  REQUIRE(shot.exit_code == 0);
  const Table connected = read_table(dir + "/connect.csv");

  const Scene scene = parse_scene(text, scene_path);
  optimize::HermiteSimpson problem(scene, optimize::read_settings(scene), 60);
  const optimize::Solution solution = optimize::solve(problem, problem.straight_line());
  REQUIRE(solution.status == optimize::Solution::Status::optimal);
  double difference = 0;
  for (int j = 0; j < problem.points(); ++j)
    for (std::size_t i = 0; i < coordinates.size(); ++i)
      difference =
          std::max(difference, std::abs(solution.z[static_cast<std::size_t>(problem.q_index(j, static_cast<int>(i)))] -
                                        connected.at(problem.time(j, solution.z.data()), coordinates[i])));
  return difference;
}

}  // namespace

TEST_CASE("optimize and connect find the same Heisenberg geodesic", "[optimize][connect]") {
  const double d = largest_difference("heisenberg", R"TOML(name = "heisenberg"
coordinates = ["x", "y", "z"]
lagrangian = "1/2*(x'^2 + y'^2)"
constraints = ["z' - (x*y' - y*x')/2"]
models = ["vakonomic"]
[initial]
t0 = 0.0
x = [0.0]
y = [0.0]
z = [0.0]
)TOML",
                                      {"x", "y", "z"}, {1.0, 0.0, 0.25});
  INFO("largest difference " << d);
  CHECK(d < 1e-5);
}

TEST_CASE("optimize and connect find the same vakonomic knife-edge motion", "[optimize][connect]") {
  const double d = largest_difference("knife_edge", R"TOML(name = "knife_edge"
coordinates = ["x", "y", "phi"]
lagrangian = "m/2*(x'^2 + y'^2) + J/2*phi'^2"
constraints = ["x'*sin(phi) - y'*cos(phi)"]
models = ["vakonomic"]
[parameters]
m = 1.0
J = 0.5
[initial]
t0 = 0.0
x = [0.0]
y = [0.0]
phi = [0.0]
)TOML",
                                      {"x", "y", "phi"}, {0.5, 0.2, 0.8});
  INFO("largest difference " << d);
  CHECK(d < 1e-5);
}
