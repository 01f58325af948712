// `nhc simulate` at the edges of events, steps and contacts (docs/events.md), each against a closed form:
//  - an event whose value is NaN or infinite is an error naming it, its expression and t (exit 3);
//  - two crossings inside one step are both found: x = sin t crossing 1 - d^2/2 twice, at
//    pi/2 -+ d (d = 4.47 ms and 0.5 ms), and a fast event cos(50 x) - cos(50 d) on a slow motion
//    x = x0 + t (IDA's steps average 30 ms, thirty times a pair's gap), zero at x = 2 pi k/50 -+ d;
//  - the first step comes from the problem's scale: x'' = A sin(w t) from rest at rtol 1e-10,
//    atol 1e-12 over t_end = 1e3 and 1e5, against x = A t/w - A sin(w t)/w^2; --max-step and
//    --initial-step set IDA's steps;
//  - a contact's normal force m g - k t reaching zero is its lift-off at t = m g/k, and a normal
//    force below zero at t0 is a lift-off at t0, not a friction shortfall;
//  - --sensitivity of a parameter only [initial] uses differentiates the start: dx/dA = cos t.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "command_runner.hpp"
#include "csv_table.hpp"

namespace {

using nhc::test::csv_columns;
using nhc::test::event_rows;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::run;
using nhc::test::Run;
using nhc::test::scratch_dir;

const double kPi = std::acos(-1.0);

/// A number to 17 significant digits.
std::string digits(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

std::string write(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

/// The number after `key` in the text (the summary's "steps 123").
long number_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  REQUIRE(at != std::string::npos);
  return std::stol(text.substr(at + key.size()));
}

/// x'' = -x from x = 0, x' = 1: x = sin t.
std::string sine(const std::string& dir, const std::string& extra) {
  return write(dir + "/sine.toml",
               "name = \"sine\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - x^2/2\"\n"
               "[initial]\nx = [0.0, 1.0]\n[simulate]\nt_end = 3.0\n" +
                   extra);
}

}  // namespace

TEST_CASE("nhc simulate: an event that is not a finite number is an error, never a crossing", "[cli][events]") {
  const std::string dir = scratch_dir("event_edges_nan");
  SECTION("2 - sqrt(x) turns NaN where x = sin t turns negative, at t = pi") {
    const std::string scene = sine(dir, "[events]\nroot = { when = \"2 - sqrt(x)\" }\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' --t-end 4 -o '" + dir + "/a.csv'", dir);
    CHECK(r.exit_code == 3);
    CHECK(r.err.find("event root (\"2 - sqrt(x)\") is NaN at t = 3.14159") != std::string::npos);
    CHECK(r.out.find("event root at") == std::string::npos);
  }
  SECTION("1/x with x(0) = 0 is infinite at t = 0") {
    const std::string scene = sine(dir, "[events]\ninverse = { when = \"1/x\" }\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/b.csv'", dir);
    CHECK(r.exit_code == 3);
    CHECK(r.err.find("event inverse (\"1/x\") is ") != std::string::npos);
    CHECK(r.err.find(" at t = 0:") != std::string::npos);
  }
}

TEST_CASE("nhc simulate: two crossings inside one step are both found", "[cli][events]") {
  const std::string dir = scratch_dir("event_edges_pairs");
  for (const double d : {std::acos(0.99999), 5e-4}) {  // 9 ms and 1 ms apart, at the default tolerances
    const std::string level = digits(std::cos(d));
    const std::string scene = sine(dir, "[events]\npeak = { when = \"x - " + level + "\", action = \"record\" }\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/p.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = event_rows(read_file(dir + "/p.events.csv"));
    REQUIRE(rows.size() == 2);
    // sin t = cos d at pi/2 -+ d. Near the top the zero moves with the solution's own error e
    // (about 1e-7 at rtol 1e-8: sin t = cos d + e), so the check is on the closed form's value
    // at the located times, one on each side of the top.
    CHECK(rows[0].second < kPi / 2);
    CHECK(rows[1].second > kPi / 2);
    CHECK(std::abs(std::sin(rows[0].second) - std::cos(d)) < 3e-7);
    CHECK(std::abs(std::sin(rows[1].second) - std::cos(d)) < 3e-7);
  }
  SECTION("a fast event on a slow motion: long steps") {
    const double d = 5e-4;  // crossings 1 ms apart around each maximum of cos(50 x)
    const std::string scene = write(dir + "/drift.toml",
                                    "name = \"drift\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2\"\n"
                                    "[initial]\nx = [0.05, 1.0]\n[simulate]\nt_end = 1.0\noutputs = 4\n"
                                    "[events]\ncomb = { when = \"cos(50*x) - " +
                                        digits(std::cos(50 * d)) + "\", action = \"record\" }\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/d.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto rows = event_rows(read_file(dir + "/d.events.csv"));
    // x = 0.05 + t reaches 2 pi k/50 -+ d for k = 1 ... 8 within t <= 1.
    REQUIRE(rows.size() == 16);
    for (int k = 1; k <= 8; ++k) {
      const double peak = 2 * kPi * k / 50 - 0.05;
      CHECK(std::abs(rows[static_cast<std::size_t>(2 * k - 2)].second - (peak - d)) < 1e-8);
      CHECK(std::abs(rows[static_cast<std::size_t>(2 * k - 1)].second - (peak + d)) < 1e-8);
    }
    // Long steps: on average more than 20 ms (33 measured), twenty times a pair's 1 ms.
    CHECK(number_after(r.out, "steps ") < 50);
  }
}

TEST_CASE("nhc simulate: the first step from the problem's scale; --max-step, --initial-step", "[cli][steps]") {
  const std::string dir = scratch_dir("event_edges_steps");
  // x'' = A sin(w t) from rest: x' = A (1 - cos w t)/w, x = A t/w - A sin(w t)/w^2.
  const double A = 2.0, w = 0.5;
  const std::string scene = write(dir + "/forced.toml",
                                  "name = \"forced\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2\"\n"
                                  "[parameters]\nA = 2.0\nw = 0.5\n[forces]\nx = \"A*sin(w*t)\"\n"
                                  "[initial]\nx = [0.0, 0.0]\n[simulate]\nrtol = 1e-10\natol = 1e-12\n"
                                  "[reference]\nx = \"A/w*t - A/w^2*sin(w*t)\"\n");
  SECTION("t_end = 1e3: the closed form to 1e-5 relative") {
    const Run r = run(nhc_command() + " simulate '" + scene + "' --t-end 1e3 -o '" + dir + "/f.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto c = csv_columns(read_file(dir + "/f.csv"));
    double worst = 0, size = 0;
    for (std::size_t i = 0; i < c.at("t").size(); ++i) {
      const double t = c.at("t")[i], exact = A * t / w - A * std::sin(w * t) / (w * w);
      worst = std::max(worst, std::abs(c.at("x")[i] - exact));
      size = std::max(size, std::abs(exact));
    }
    CHECK(c.at("t").back() == 1e3);
    CHECK(worst < 1e-5 * size);
  }
  SECTION("t_end = 1e5 (w = 0.01, 159 periods within the default step limit): exit 0 with the reference error") {
    const Run r = run(nhc_command() + " simulate '" + scene + "' --t-end 1e5 --set w=0.01 -o '" + dir + "/g.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const auto at = r.out.find("max reference error ");
    REQUIRE(at != std::string::npos);
    // |x| reaches A t_end / w = 2e7 there.
    CHECK(std::stod(r.out.substr(at + 20)) < 1e-5 * A * 1e5 / 0.01);
  }
  SECTION("--max-step bounds IDA's steps, --initial-step sets the first") {
    Run r = run(nhc_command() + " simulate '" + scene + "' --t-end 10 --max-step 0.01 --initial-step 1e-6", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(number_after(r.out, "steps ") >= 1000);  // 10 / 0.01
    r = run(nhc_command() + " simulate '" + scene + "' --max-step -1", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--max-step") != std::string::npos);
    r = run(nhc_command() + " simulate '" + scene + "' --integrator variational --step 0.01 --max-step 0.1", dir);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--max-step sets IDA's steps; --integrator variational takes the fixed step --step H") !=
          std::string::npos);
  }
}

TEST_CASE("nhc simulate: a contact lifts off where its normal force reaches zero", "[cli][contacts]") {
  const std::string dir = scratch_dir("event_edges_liftoff");
  // A cylinder rolling at constant speed on a flat floor: no tangential force; the floor's push
  // m g - k t (a load lifted off it) reaches zero at t = m g/k.
  const auto floor = [&](const std::string& normal) {
    return write(dir + "/floor.toml",
                 "name = \"floor\"\ncoordinates = [\"s\", \"th\"]\n"
                 "lagrangian = \"m/2*s'^2 + m*r^2/4*th'^2\"\nconstraints = [\"s' - r*th'\"]\nmodels = [\"chetaev\"]\n"
                 "[parameters]\nm = 2.0\nr = 0.3\ng = 9.81\nk = 10.0\n"
                 "[initial]\ns = [0.0, 0.5]\nth = [0.0, \"0.5/r\"]\n"
                 "[simulate]\nt_end = 4.0\nrtol = 1e-10\natol = 1e-12\n"
                 "[contacts.floor]\nnormal = \"" +
                     normal + "\"\nrolling = [1]\nmu = 0.3\n");
  };
  SECTION("m g - k t: lift-off at t = m g/k, exit 0") {
    const Run r = run(nhc_command() + " simulate '" + floor("m*g - k*t") + "' -o '" + dir + "/l.csv'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("contact floor lifts off at t = 1.962") != std::string::npos);  // 2 * 9.81 / 10
    CHECK(r.out.find("slips") == std::string::npos);
    const auto rows = event_rows(read_file(dir + "/l.events.csv"));
    REQUIRE(rows.size() == 1);
    CHECK(rows[0].first == "floor.liftoff");
    CHECK(std::abs(rows[0].second - 2.0 * 9.81 / 10.0) < 1e-9);
  }
  SECTION("a normal force below zero at t0 is a lift-off at t0") {
    const Run r = run(nhc_command() + " simulate '" + floor("m*g - k*(t + 3)") + "' -o '" + dir + "/m.csv'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("contact floor lifts off at t = 0 (its normal force \"m*g - k*(t + 3)\" is -10.38") !=
          std::string::npos);
    CHECK(r.out.find("needs mu >= -") == std::string::npos);
    CHECK(r.out.find("slips") == std::string::npos);
  }
}

TEST_CASE("nhc simulate --sensitivity: a parameter only [initial] uses moves the start", "[cli][sensitivity]") {
  const std::string dir = scratch_dir("event_edges_sensitivity");
  // x'' = -x from x(0) = A, x'(0) = 0: x = A cos t, so dx/dA = cos t although no equation reads A
  // (s(t0) = dx(0)/dA = 1, dF/dA = 0).
  const std::string scene = write(dir + "/start.toml",
                                  "name = \"start\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - x^2/2\"\n"
                                  "[parameters]\nA = 0.7\nB = 0.1\nTend = 3.0\n[initial]\nx = [\"A\", 0.0]\n"
                                  "[simulate]\nt_end = \"Tend\"\nrtol = 1e-10\natol = 1e-12\n");
  Run r = run(nhc_command() + " simulate '" + scene + "' --sensitivity A -o '" + dir + "/s.csv'", dir);
  REQUIRE(r.exit_code == 0);
  const auto csv = csv_columns(read_file(dir + "/s.csv"));
  REQUIRE(csv.count("d(x)/d(A)") == 1);
  double worst = 0;
  for (std::size_t i = 0; i < csv.at("t").size(); ++i)
    worst = std::max(worst, std::abs(csv.at("d(x)/d(A)")[i] - std::cos(csv.at("t")[i])));
  CHECK(worst < 1e-7);
  CHECK(csv.at("t").back() == 3.0);
  r = run(nhc_command() + " simulate '" + scene + "' --sensitivity B", dir);  // read by nothing
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("its sensitivities are all zero") != std::string::npos);
  // Read by [simulate] t_end only: the refusal names it.
  r = run(nhc_command() + " simulate '" + scene + "' --sensitivity Tend", dir);
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("only the scene's [simulate] t_end (" + scene +
                   ":11:9) does, which --sensitivity does not follow") != std::string::npos);
}
