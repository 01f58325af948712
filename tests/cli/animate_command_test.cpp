// `nhc animate` (docs/animate.md) on a pendulum (tests/cli/scenes/visual_pendulum.toml):
// the page's samples of the bob against the bob computed from the CSV of `nhc simulate` (the same
// run), its sizes and rotation; three.js beside the page; refusals (no [visual], an output that is
// the scene) exit 2 and leave nothing; a run that fails part way keeps its page and exits 3.
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

const std::string kScene = std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/visual_pendulum.toml";

/// The numbers of the JSON array that follows `"key":` after `from` in the page.
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

/// Column `name` of a CSV.
std::vector<double> column(const std::string& csv, const std::string& name) {
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

}  // namespace

TEST_CASE("nhc animate: the page holds the shapes along the run", "[cli][animate]") {
  const std::string dir = scratch_dir("animate_page");
  const Run sim = run(nhc_command() + " simulate '" + kScene + "' --outputs 60 -o '" + dir + "/run.csv'", dir);
  REQUIRE(sim.exit_code == 0);
  const Run r = run(nhc_command() + " animate '" + kScene + "' --outputs 60 -o '" + dir + "/page'", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("61 samples, 3 shapes") != std::string::npos);
  CHECK(file_exists(dir + "/page/three.min.js"));
  CHECK(file_exists(dir + "/page/OrbitControls.js"));
  const std::string page = read_file(dir + "/page/index.html");
  const std::vector<double> t = array_after(page, "t");
  const std::string csv = read_file(dir + "/run.csv");
  const std::vector<double> th = column(csv, "th");
  const std::vector<double> th_rate = column(csv, "th'"), w5 = column(csv, "w5_out");
  for (std::size_t k = 0; k < th.size(); ++k)
    CHECK(w5[k] == Approx(std::pow(th[k] + th_rate[k] + 1, 5)).epsilon(1e-12));
  REQUIRE(t.size() == 61);
  REQUIRE(th.size() == 61);
  const std::size_t ball = page.find("\"name\":\"ball\"");
  REQUIRE(ball != std::string::npos);
  const std::vector<double> centre = array_after(page, "position", ball);
  const std::vector<double> rotation = array_after(page, "rotation", ball);
  REQUIRE(centre.size() == 3 * 61);
  REQUIRE(rotation.size() == 9 * 61);
  double worst = 0;
  for (std::size_t k = 0; k < 61; ++k) {
    // The bob at (l sin th, 0, -l cos th), l = 2; roty(-th) has entry (1, 3) = -sin th.
    worst =
        std::max({worst, std::abs(centre[3 * k] - 2 * std::sin(th[k])), std::abs(centre[3 * k + 1]),
                  std::abs(centre[3 * k + 2] + 2 * std::cos(th[k])), std::abs(rotation[9 * k + 2] + std::sin(th[k]))});
  }
  CHECK(worst < 1e-8);  // the page keeps 9 significant digits
  CHECK(array_after(page, "t").back() == Approx(3.0));
  CHECK(page.find("\"radius\":0.2") != std::string::npos);  // l/10
  const std::size_t rod = page.find("\"name\":\"rod\"");
  REQUIRE(rod != std::string::npos);
  CHECK(array_after(page, "to", rod).size() == 3 * 61);
  CHECK(page.find("\"color\":\"#333333\"", rod) != std::string::npos);
}

TEST_CASE("nhc animate: refusals leave nothing, a failed run keeps its page", "[cli][animate]") {
  const std::string dir = scratch_dir("animate_refusals");
  SECTION("a scene without [visual]") {
    const Run r = run(
        nhc_command() + " animate '" + std::string(NHC_SOURCE_DIR) + "/examples/particle.toml' -o '" + dir + "/page'",
        dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("no [visual] table") != std::string::npos);
    CHECK_FALSE(file_exists(dir + "/page"));
  }
  SECTION("the output is the scene itself") {
    const Run r = run(nhc_command() + " animate '" + kScene + "' -o '" + kScene + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK(read_file(kScene).find("[visual]") != std::string::npos);
  }
  SECTION("-o is required") {
    const Run r = run(nhc_command() + " animate '" + kScene + "'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("-o") != std::string::npos);
  }
  SECTION("Appell-Hamel stops at t* = v0 (a^2 + b^2)/(g a b): the page shows the motion up to there") {
    const std::string scene = dir + "/appell_hamel.toml";
    {
      std::ofstream out(scene);
      out << read_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml")
          << "\n[visual]\nmass = { shape = \"sphere\", radius = 0.05, center = \"[x, y, z]\" }\n";
    }
    const Run r = run(nhc_command() + " animate '" + scene + "' --t-end 2 -o '" + dir + "/page'", dir);
    CHECK(r.exit_code == 3);
    CHECK(r.err.find("the page shows the motion up to there") != std::string::npos);
    REQUIRE(file_exists(dir + "/page/index.html"));
    const std::vector<double> t = array_after(read_file(dir + "/page/index.html"), "t");
    CHECK(t.back() < 2.0);
  }
}

TEST_CASE("nhc animate: sample times after a late t0 stay distinct, the summary says their range", "[cli][animate]") {
  const std::string dir = scratch_dir("animate_late_t0");
  // t0 = 1e6, 1001 samples 0.01 apart: with 9 significant digits they were 101 distinct times.
  std::string text = read_file(kScene);
  text.replace(text.find("[initial]\n"), 10, "[initial]\nt0 = 1000000.0\n");
  text.replace(text.find("t_end = 3.0"), 11, "t_end = 1000010.0");
  const std::string scene = dir + "/late.toml";
  std::ofstream(scene) << text;
  // rtol 1e-8: at the scene's 1e-10 IDA's first steps fall below the collapse test's 1e-12 |t| there.
  const Run r = run(
      nhc_command() + " animate '" + scene + "' --outputs 1000 --rtol 1e-8 --atol 1e-10 -o '" + dir + "/page'", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("t from 1000000 to 1000010, 1001 samples") != std::string::npos);
  const std::vector<double> t = array_after(read_file(dir + "/page/index.html"), "t");
  REQUIRE(t.size() == 1001);
  for (std::size_t k = 0; k < t.size(); ++k) CHECK(t[k] == 1e6 + 10.0 * static_cast<double>(k) / 1000);
}
