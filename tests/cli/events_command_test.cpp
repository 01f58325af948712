// `nhc simulate` with [events] and --stop-when on x'' = -4 x from x = 1 at rest, x = cos(2 t):
// x crosses zero downwards at pi/4, upwards at 3 pi/4 (closed form). The summary names each
// event, <stem>.events.csv holds `name,t`, a stop event ends the CSV at the crossing with exit 0;
// a bad expression is exit 2 naming the flag or FILE:LINE:COLUMN.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "command_runner.hpp"
#include "csv_table.hpp"

namespace {

using nhc::test::event_rows;
using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::run;
using nhc::test::Run;
using nhc::test::scratch_dir;

const double kPi = std::acos(-1.0);

std::string write_scene(const std::string& dir, const std::string& events) {
  const std::string path = dir + "/oscillator.toml";
  std::ofstream(path) << "name = \"oscillator\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - 2*x^2\"\n"
                         "[initial]\nx = [1.0, 0.0]\n[simulate]\nt_end = 4.0\nrtol = 1e-10\natol = 1e-12\n"
                      << events;
  return path;
}

/// The t of the CSV's last row.
double last_t(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return std::stod(last.substr(0, last.find(',')));
}

}  // namespace

TEST_CASE("nhc simulate: [events] and --stop-when at the closed form's zero crossings", "[cli][events]") {
  const std::string dir = scratch_dir("events_command");
  SECTION("recorded events in both directions, then a stop") {
    const std::string scene =
        write_scene(dir,
                    "[events]\ndown = { when = \"x\", direction = \"down\", action = \"record\" }\n"
                    "up = { when = \"x\", direction = \"up\", action = \"stop\" }\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/x.csv'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("  event down at t = 0.78539816") != std::string::npos);  // pi/4 to the tolerance
    CHECK(r.out.find("  event up at t = 2.3561944") != std::string::npos);
    const auto rows = event_rows(read_file(dir + "/x.events.csv"));
    REQUIRE(rows.size() == 2);
    CHECK(rows[0].first == "down");
    CHECK(std::abs(rows[0].second - kPi / 4) < 1e-8);
    CHECK(rows[1].first == "up");
    CHECK(std::abs(rows[1].second - 3 * kPi / 4) < 1e-8);
    CHECK(last_t(read_file(dir + "/x.csv")) == rows[1].second);  // the run ends at the stop event
  }
  SECTION("--stop-when") {
    const std::string scene = write_scene(dir, "");
    const Run r = run(nhc_command() + " simulate '" + scene + "' --stop-when 'x + 0.5' -o '" + dir + "/y.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = event_rows(read_file(dir + "/y.events.csv"));
    REQUIRE(rows.size() == 1);
    CHECK(rows[0].first == "stop_when");
    CHECK(std::abs(rows[0].second - std::acos(-0.5) / 2) < 1e-8);  // cos(2 t) = -1/2
  }
  SECTION("bad events: exit 2, nothing written") {
    const std::string scene = write_scene(dir, "");
    Run r = run(nhc_command() + " simulate '" + scene + "' --stop-when 'x +' -o '" + dir + "/z.csv'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--stop-when") != std::string::npos);
    CHECK(!file_exists(dir + "/z.csv"));
    const std::string bad = write_scene(dir, "[events]\ne = { when = \"x\", action = \"explode\" }\n");
    r = run(nhc_command() + " simulate '" + bad + "' -o '" + dir + "/z.csv'", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("oscillator.toml:11:") != std::string::npos);
    CHECK(r.err.find("action 'explode': stop or record") != std::string::npos);
  }
}
