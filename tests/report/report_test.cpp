// nhc report end to end: the Appell–Hamel work-precision report and the stiff and extreme scenes
// of examples/ (docs/stability.md), asserted on the numbers of workprec.csv.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using nhc::test::Run;

/// workprec.csv as rows of column name → text.
using Row = std::map<std::string, std::string>;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::vector<Row> read_csv(const std::string& path) {
  std::stringstream in(nhc::test::read_file(path));
  std::string line;
  std::vector<Row> rows;
  if (!std::getline(in, line)) return rows;
  const std::vector<std::string> header = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    Row row;
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

double num(const Row& row, const std::string& column) {
  const auto it = row.find(column);
  REQUIRE(it != row.end());
  return std::strtod(it->second.c_str(), nullptr);
}

/// Runs `nhc report` from the source directory into a fresh directory; returns (run, rows).
std::pair<Run, std::vector<Row>> report(const std::string& name, const std::string& args) {
  const std::string dir = nhc::test::scratch_dir("report_" + name);
  const Run r = nhc::test::run(std::string("cd '") + NHC_SOURCE_DIR + "' && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                                   "/tests/report/nhc-cache' " + nhc::test::nhc_command() + " report " + args +
                                   " -o '" + dir + "/out'",
                               dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  return {r, read_csv(dir + "/out/workprec.csv")};
}

}  // namespace

TEST_CASE("nhc report on Appell–Hamel writes the CSV, both plots and the report", "[report]") {
  const std::string dir = nhc::test::scratch_dir("report_appell_hamel");
  const Run r = nhc::test::run(std::string("cd '") + NHC_SOURCE_DIR + "' && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                                   "/tests/report/nhc-cache' " + nhc::test::nhc_command() +
                                   " report examples/appell_hamel.toml -o '" + dir + "/out'",
                               dir);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  for (const char* f : {"workprec.csv", "workprec.svg", "workprec.png", "report.md"})
    CHECK(nhc::test::file_exists(dir + "/out/" + f));
  CHECK(nhc::test::read_file(dir + "/out/workprec.svg").find("<svg") != std::string::npos);
  CHECK(nhc::test::read_file(dir + "/out/workprec.png").substr(1, 3) == "PNG");
  const std::string md = nhc::test::read_file(dir + "/out/report.md");
  CHECK(md.find("![workprec](workprec.svg)") != std::string::npos);
  CHECK(md.find("reference run at rtol 1e-13") != std::string::npos);
  CHECK(md.find("R_x") != std::string::npos);  // the equations

  const std::vector<Row> rows = read_csv(dir + "/out/workprec.csv");
  // Default: rtol 1e-3 … 1e-12 (10 decades) × dense/sparse × without/with projection.
  REQUIRE(rows.size() == 40);
  std::map<std::string, std::vector<const Row*>> series;
  for (const Row& row : rows) series[row.at("configuration")].push_back(&row);
  REQUIRE(series.size() == 4);
  for (const auto& [config, rs] : series) {
    INFO(config);
    REQUIRE(rs.size() == 10);
    CHECK(num(*rs.front(), "rtol") == Approx(1e-3));
    CHECK(num(*rs.back(), "rtol") == Approx(1e-12));
    for (const Row* row : rs) {
      CHECK(row->at("status") == "ok");
      CHECK(row->at("error_source") == "reference run");
      CHECK(num(*row, "steps") > 0);
      CHECK(num(*row, "seconds") > 0);
      // The error follows the tolerance: never more than 10 rtol (atol = rtol/100 here) …
      CHECK(num(*row, "error") <= 10 * num(*row, "rtol"));
    }
    // … falls by orders of magnitude from the loosest to the tightest, down to the reference's
    // accuracy (rtol 1e-13), and the steps grow.
    CHECK(num(*rs.back(), "error") < 1e-4 * num(*rs.front(), "error"));
    CHECK(num(*rs.back(), "error") < 1e-12);
    CHECK(num(*rs.back(), "steps") > num(*rs.front(), "steps"));
  }
}

TEST_CASE("stiff scenes: the accuracy is met and the steps stay bounded for K = 1e2 … 1e8", "[report]") {
  {
    const auto [r, rows] = report("particle_spring",
                                  "examples/particle_spring.toml --sweep K=1e2:1e8 --tolerances 1e-6 "
                                  "--jacobian dense --projection off");
    REQUIRE(rows.size() == 7);
    CHECK(num(rows.front(), "value") == Approx(1e2));
    CHECK(num(rows.back(), "value") == Approx(1e8));
    for (const Row& row : rows) {
      INFO("K = " << row.at("value"));
      CHECK(row.at("status") == "ok");
      CHECK(row.at("error_source") == "reference");
      CHECK(num(row, "error") < 1e-12);
      CHECK(num(row, "steps") <= 100);
      CHECK(num(row, "steps") <= 1.5 * num(rows.front(), "steps"));
    }
  }
  {
    const auto [r, rows] = report("appell_hamel_spring",
                                  "examples/appell_hamel_spring.toml --sweep K=1e2:1e8 "
                                  "--tolerances 1e-6 --jacobian dense --projection off");
    REQUIRE(rows.size() == 7);
    for (const Row& row : rows) {
      INFO("K = " << row.at("value"));
      CHECK(row.at("status") == "ok");
      CHECK(num(row, "error") < 1e-5);
    }
    // Bounded for every K: the algebraic multiplier, which a stiff spring makes noisy, is kept
    // out of IDA's error test (IntegratorOptions::algebraic_in_error_test).
    for (const Row& row : rows) {
      INFO("K = " << row.at("value"));
      CHECK(num(row, "steps") <= 100);
      CHECK(num(row, "steps") <= 1.5 * num(rows.front(), "steps"));
    }
  }
}

TEST_CASE("extreme scenes meet their accuracy or stop with their diagnostic", "[report]") {
  {
    // v0 = 1e-6: stops at t* = v0 (a^2 + b^2)/(g a b), exact up to there.
    const auto [r, rows] = report("near_singular",
                                  "examples/appell_hamel_near_singular.toml --tolerances 1e-6:1e-9 "
                                  "--jacobian dense --projection off");
    REQUIRE(rows.size() == 4);
    const double t_star = 1e-6 * 1.25 / (9.81 * 0.5);
    for (const Row& row : rows) {
      CHECK(row.at("status") == "singular_constraint_gradient");
      CHECK(num(row, "t_reached") == Approx(t_star).epsilon(1e-6));
      CHECK(num(row, "error") < 1e-18);
    }
  }
  for (const char* scene : {"appell_hamel_tiny_mass", "appell_hamel_huge_mass"}) {
    INFO(scene);
    const auto [r, rows] =
        report(scene, std::string("examples/") + scene + ".toml --tolerances 1e-6:1e-8 --jacobian dense");
    REQUIRE(rows.size() == 6);
    for (const Row& row : rows) {
      CHECK(row.at("status") == "ok");
      CHECK(num(row, "error") < 100 * num(row, "rtol"));
    }
  }
  {
    // t_end = 1e4: the hidden-constraint drift is smaller with projection, the accuracy met.
    const auto [r, rows] =
        report("orbit", "examples/appell_hamel_orbit.toml --tolerances 1e-8 --jacobian dense --projection both");
    REQUIRE(rows.size() == 2);
    CHECK(rows[0].at("projection") == "0");
    CHECK(rows[1].at("projection") == "1");
    for (const Row& row : rows) {
      CHECK(row.at("status") == "ok");
      CHECK(num(row, "t_reached") == Approx(1e4));
      CHECK(num(row, "error") < 1e-4);
      CHECK(num(row, "max_hidden_drift") < 1e-7);
    }
    // Measured 4.4e-9 without and 4.4e-10 with projection (9.9 times smaller).
    CHECK(num(rows[1], "max_hidden_drift") < 0.2 * num(rows[0], "max_hidden_drift"));
    CHECK(num(rows[1], "projections") > 0);
  }
  {
    const auto [r, rows] = report("particle", "examples/particle.toml --tolerances 1e-6:1e-8 --jacobian dense");
    for (const Row& row : rows) {
      CHECK(row.at("error_source") == "reference");
      CHECK(num(row, "error") < 1e-10);
    }
  }
  {
    // Third-order constraint: against a reference run; the error falls with the tolerance.
    const auto [r, rows] =
        report("third_order", "examples/third_order.toml --tolerances 1e-4:1e-8 --jacobian dense --projection off");
    REQUIRE(rows.size() == 5);
    for (const Row& row : rows) {
      CHECK(row.at("status") == "ok");
      CHECK(row.at("error_source") == "reference run");
      CHECK(num(row, "error") < 100 * num(row, "rtol"));
    }
    CHECK(num(rows.back(), "error") < 1e-2 * num(rows.front(), "error"));
  }
}

TEST_CASE("nhc report rejects bad flags with exit code 2", "[report]") {
  const std::string dir = nhc::test::scratch_dir("report_bad");
  const std::string base = std::string("cd '") + NHC_SOURCE_DIR + "' && " + nhc::test::nhc_command() + " report ";
  CHECK(nhc::test::run(base + "examples/particle.toml --tolerances 1e-8:1e-3 -o '" + dir + "/o'", dir).exit_code == 2);
  CHECK(nhc::test::run(base + "examples/particle.toml --set nope=1 -o '" + dir + "/o'", dir).exit_code == 2);
  CHECK(nhc::test::run(base + "examples/particle.toml --sweep K -o '" + dir + "/o'", dir).exit_code == 2);
}
