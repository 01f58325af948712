// One consistent initialization: `nhc analyze` (GiNaC-evaluated constraints, no compiler) and
// `nhc simulate` (the generated model, the runtime) report the same point at t0 for every
// example scene under its [simulate] model and for both models of the paper's examples.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <cmath>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using nhc::test::Run;

struct AnalyzedValue {
  double value = 0;
  std::string source;
};

/// "name": {"value": v, "source": "s"} entries of `nhc analyze --format json`.
std::map<std::string, AnalyzedValue> analyzed_point(const std::string& json) {
  std::map<std::string, AnalyzedValue> out;
  static const std::regex entry("\"([^\"]+)\": \\{\\s*\"value\": ([-+0-9.eE]+),\\s*\"source\": \"([a-z]+)\"\\s*\\}");
  for (auto it = std::sregex_iterator(json.begin(), json.end(), entry); it != std::sregex_iterator(); ++it)
    out[(*it)[1]] = {std::stod((*it)[2]), (*it)[3]};
  return out;
}

/// The first data row of a CSV written by `nhc simulate`, by column name.
std::map<std::string, double> first_row(const std::string& csv) {
  std::istringstream in(csv);
  std::string header, row, cell;
  std::getline(in, header);
  std::getline(in, row);
  std::vector<std::string> names;
  std::istringstream h(header), r(row);
  while (std::getline(h, cell, ',')) names.push_back(cell);
  std::map<std::string, double> out;
  for (const auto& name : names) {
    if (!std::getline(r, cell, ',')) break;
    out[name] = std::stod(cell);
  }
  return out;
}

void check_same_point(const std::string& scene, const std::string& model) {
  const std::string dir = nhc::test::scratch_dir("same_point_" + std::to_string(::getpid()));
  const std::string in_source = std::string("cd '") + NHC_SOURCE_DIR + "' && ";
  const Run analyzed = nhc::test::run(
      in_source + nhc::test::nhc_command() + " analyze " + scene + " --model " + model + " --format json", dir);
  const Run simulated =
      nhc::test::run(in_source + "NHC_CACHE_DIR='" + dir + "/cache' " + nhc::test::nhc_command() + " simulate " +
                         scene + " --model " + model + " --t-end 1e-3 -o '" + dir + "/run.csv'",
                     dir);
  INFO(scene << " " << model << "\n" << analyzed.err << simulated.err);
  if (analyzed.exit_code != 0) {
    // No consistent point (a singular Jacobian at t0): the integration cannot start either.
    CHECK(analyzed.exit_code == 3);
    CHECK(simulated.exit_code == 3);
    return;
  }
  REQUIRE(nhc::test::file_exists(dir + "/run.csv"));
  const auto point = analyzed_point(analyzed.out);
  const auto row = first_row(nhc::test::read_file(dir + "/run.csv"));
  REQUIRE(point.size() >= 2);
  for (const auto& [name, v] : point) {
    INFO(name << " (" << v.source << ")");
    const auto it = row.find(name);
    REQUIRE(it != row.end());
    // The initial values come from one solver with one tolerance (base::solve_constraints):
    // equal to rounding. The leading derivatives solve the same nonsingular system, by Newton
    // (analyze) and IDACalcIC (simulate): equal to the integration tolerance.
    const double tolerance = v.source == "computed" ? 1e-6 : 1e-12;
    CHECK(std::abs(it->second - v.value) <= tolerance * (1.0 + std::abs(v.value)));
  }
}

}  // namespace

TEST_CASE("nhc analyze and nhc simulate start from the same consistent point", "[sigma][runtime]") {
  // Appell–Hamel under Chetaev's model, the README's example: z'(0) = (b/a) sqrt(x'² + y'²)
  // = 0.5 sqrt(1.25) = 0.5590169944 solved from f1 = 0; λ1(0) computed.
  check_same_point("examples/appell_hamel.toml", "chetaev");
  check_same_point("examples/appell_hamel.toml", "suslov");
  check_same_point("examples/particle.toml", "vakonomic");
  // Every other example scene under its [simulate] model (the paper's vakonomic singular start:
  // neither command finds a point).
  for (const char* scene :
       {"appell_hamel_huge_mass", "appell_hamel_near_singular", "appell_hamel_orbit", "appell_hamel_spring",
        "appell_hamel_tiny_mass", "particle", "particle_spring", "third_order"})
    check_same_point(std::string("examples/") + scene + ".toml", "chetaev");
  check_same_point("examples/appell_hamel_vakonomic_singular.toml", "vakonomic");
}
