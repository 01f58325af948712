// `nhc simulate` with [contacts] (docs/contacts.md) against closed forms. A uniform cylinder
// (mass m, radius r, I = m r^2/2) rolling down an incline of angle alpha, the contact written as
// the gap n = 0 (its multiplier the normal force) and the slip velocity s' - r th' = 0: rolling
// needs F_t = m g sin(alpha)/3 up the slope against F_n = m g cos(alpha), the ratio tan(alpha)/3
// (docs/contacts.md, eq. (4)); with mu below it the contact slips at t = 0. The same cylinder on a
// flat floor (F_n = "m*g", an expression) driven by a torque k t needs F_t = 2 k t/(3 r): it slips
// where that reaches mu m g, at t = 3 mu m g r/(2 k) (eq. (5)), located by IDA's root finding.
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
using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::run;
using nhc::test::Run;
using nhc::test::scratch_dir;

constexpr double kM = 2.0, kR = 0.3, kG = 9.81, kAlpha = 0.5;

std::string incline(const std::string& dir, const std::string& contact) {
  const std::string path = dir + "/incline.toml";
  std::ofstream(path) << "name = \"incline\"\ncoordinates = [\"s\", \"n\", \"th\"]\n"
                         "lagrangian = \"m/2*(s'^2 + n'^2) + m*r^2/4*th'^2 + m*g*(s*sin(alpha) - n*cos(alpha))\"\n"
                         "constraints = [\"n\", \"s' - r*th'\"]\nmodels = [\"chetaev\"]\n"
                         "[parameters]\nm = 2.0\nr = 0.3\ng = 9.81\nalpha = 0.5\n"
                         "[initial]\ns = [0.0, 0.5]\nn = [0.0, 0.0]\nth = [0.0, \"0.5/r\"]\n"
                         "[simulate]\nt_end = 1.0\noutputs = 10\nrtol = 1e-10\natol = 1e-12\n"
                      << contact;
  return path;
}

}  // namespace

TEST_CASE("nhc simulate: [contacts] forces and slip against closed forms", "[cli][contacts]") {
  const std::string dir = scratch_dir("contacts_command");
  const double ratio = std::tan(kAlpha) / 3;
  SECTION("a cylinder rolling down an incline: the friction ratio tan(alpha)/3, friction up the slope") {
    const std::string scene = incline(dir, "[contacts.floor]\nnormal = \"lambda1\"\nrolling = [2]\nmu = 0.3\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/roll.csv'", dir);
    REQUIRE(r.exit_code == 0);
    auto c = csv_columns(read_file(dir + "/roll.csv"));
    REQUIRE(c["t"].size() == 11);
    for (std::size_t i = 0; i < c["t"].size(); ++i) {
      CHECK(std::abs(c["floor.ratio"][i] - ratio) < 1e-10);
      CHECK(std::abs(c["floor.normal"][i] - kM * kG * std::cos(kAlpha)) < 1e-9);
      CHECK(std::abs(c["floor.tangential"][i] - kM * kG * std::sin(kAlpha) / 3) < 1e-9);
      // lambda2 is the component along +s, down the slope: negative, friction pushes up it.
      CHECK(std::abs(c["lambda2"][i] + kM * kG * std::sin(kAlpha) / 3) < 1e-9);
      CHECK(c["floor.state"][i] == 1);
    }
    CHECK(read_file(dir + "/roll.events.csv") == "name,t\n");
  }
  SECTION("mu below tan(alpha)/3: the contact slips at t = 0, exit 0") {
    const std::string scene =
        incline(dir, "[contacts.floor]\nnormal = \"lambda1\"\nrolling = [2]\nmu = 0.1\non_slip = \"stop\"\n");
    const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/slip.csv'", dir);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("  contact floor slips at t = 0 (needs mu >= 0.182101)\n") != std::string::npos);
    CHECK(read_file(dir + "/slip.events.csv") == "name,t\nfloor.slip,0\n");
    CHECK(csv_columns(read_file(dir + "/slip.csv"))["t"].size() == 1);
  }
  SECTION("a torque k t on a flat floor: the slip at t = 3 mu m g r/(2 k), by root finding") {
    const std::string path = dir + "/floor.toml";
    std::ofstream(path) << "name = \"floor\"\ncoordinates = [\"s\", \"th\"]\n"
                           "lagrangian = \"m/2*s'^2 + m*r^2/4*th'^2\"\nconstraints = [\"s' - r*th'\"]\n"
                           "models = [\"chetaev\"]\n[parameters]\nm = 2.0\nr = 0.3\ng = 9.81\nk = 5.0\n"
                           "[forces]\nth = \"k*t\"\n[initial]\ns = [0.0, 0.0]\nth = [0.0, 0.0]\n"
                           "[simulate]\nt_end = 2.0\nrtol = 1e-10\natol = 1e-12\n"
                           "[contacts.floor]\nnormal = \"m*g\"\nrolling = [1]\nmu = 0.5\n";
    const Run r = run(nhc_command() + " simulate '" + path + "' -o '" + dir + "/torque.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const double t_slip = 3 * 0.5 * kM * kG * kR / (2 * 5.0);
    CHECK(r.out.find("contact floor slips at t = 0.8829") != std::string::npos);
    CHECK(r.out.find("(needs mu >= 0.5)") != std::string::npos);
    const std::string events = read_file(dir + "/torque.events.csv");
    REQUIRE(events.rfind("name,t\nfloor.slip,", 0) == 0);
    CHECK(std::abs(std::stod(events.substr(std::string("name,t\nfloor.slip,").size())) - t_slip) < 1e-8);
    auto c = csv_columns(read_file(dir + "/torque.csv"));
    CHECK(c["t"].back() == Approx(t_slip).margin(1e-8));
    CHECK(std::abs(c["floor.ratio"].back() - 0.5) < 1e-7);
  }
  SECTION("a cylinder launched sliding without spin: rolling at t = v0/(3 mu g), v = 2 v0/3") {
    // docs/contacts.md, eq. (6): the sliding model (on_slip = "slide") until the stick, then rolling.
    const std::string path = dir + "/launched.toml";
    std::ofstream(path) << "name = \"launched\"\ncoordinates = [\"x\", \"th\"]\n"
                           "lagrangian = \"m/2*x'^2 + m*r^2/4*th'^2\"\nconstraints = [\"x' - r*th'\"]\n"
                           "models = [\"chetaev\"]\n[parameters]\nm = 2.0\nr = 0.3\ng = 9.81\n"
                           "[initial]\nx = [0.0, 3.0]\nth = [0.0, 0.0]\n"
                           "[simulate]\nt_end = 1.0\noutputs = 400\nrtol = 1e-10\natol = 1e-12\n"
                           "[contacts.floor]\nnormal = \"m*g\"\nrolling = [1]\nmu = 0.2\non_slip = \"slide\"\n";
    const Run r = run(nhc_command() + " simulate '" + path + "' -o '" + dir + "/launched.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const double v0 = 3.0, mu = 0.2, t_roll = v0 / (3 * mu * kG);
    const std::string events = read_file(dir + "/launched.events.csv");
    REQUIRE(events.rfind("name,t\nfloor.stick,", 0) == 0);
    CHECK(std::abs(std::stod(events.substr(std::string("name,t\nfloor.stick,").size())) - t_roll) < 1e-8);
    auto c = csv_columns(read_file(dir + "/launched.csv"));
    const std::size_t n = c["t"].size();
    REQUIRE(n == 402);  // the 401 output times and the last sliding point
    double work = 0;    // of friction, trapezoidal: its integrand mu m g |x' - r th'| is linear while sliding
    const auto energy = [&](std::size_t i) {
      return kM / 2 * std::pow(c["x'"][i], 2) + kM * kR * kR / 4 * std::pow(c["th'"][i], 2);
    };
    const auto power = [&](std::size_t i) {
      return c["floor.tangential"][i] * std::abs(c["x'"][i] - kR * c["th'"][i]);
    };
    for (std::size_t i = 0; i < n; ++i) {
      const double t = c["t"][i];
      if (i > 0) work += (t - c["t"][i - 1]) * (power(i) + power(i - 1)) / 2;
      CHECK(std::abs(energy(0) - energy(i) - work) < 1e-8);  // the energy lost is the work of friction
      if (t < t_roll - 1e-7) {
        CHECK(c["floor.state"][i] == 0);
        CHECK(std::abs(c["floor.tangential"][i] - mu * kM * kG) < 1e-9);  // mu m g
        CHECK(std::abs(c["x'"][i] - (v0 - mu * kG * t)) < 1e-8);
        CHECK(std::abs(kR * c["th'"][i] - 2 * mu * kG * t) < 1e-8);
      } else if (t > t_roll + 1e-7) {
        CHECK(c["floor.state"][i] == 1);
        CHECK(std::abs(c["floor.tangential"][i]) < 1e-9);  // rolling on a level floor needs no friction
        CHECK(std::abs(c["x'"][i] - 2 * v0 / 3) < 1e-8);
        CHECK(std::abs(kR * c["th'"][i] - 2 * v0 / 3) < 1e-8);
      }
    }
    CHECK(std::abs(work - kM * v0 * v0 / 6) < 1e-8);  // m v0^2/6 in all
  }
  SECTION("a torque k t: rolling, the slip at 3 mu m g r/(2 k), then sliding (closed forms)") {
    // Rolling: x'' = k t/(3/2 m r), so x' = k t^2/(3 m r). Sliding: m x'' = mu m g, I th'' = k t - mu m g r.
    const std::string path = dir + "/spin.toml";
    std::ofstream(path) << "name = \"spin\"\ncoordinates = [\"x\", \"th\"]\n"
                           "lagrangian = \"m/2*x'^2 + m*r^2/4*th'^2\"\nconstraints = [\"x' - r*th'\"]\n"
                           "models = [\"chetaev\"]\n[parameters]\nm = 2.0\nr = 0.3\ng = 9.81\nk = 5.0\n"
                           "[forces]\nth = \"k*t\"\n[initial]\nx = [0.0, 0.0]\nth = [0.0, 0.0]\n"
                           "[simulate]\nt_end = 1.5\noutputs = 30\nrtol = 1e-10\natol = 1e-12\n"
                           "[contacts.floor]\nnormal = \"m*g\"\nrolling = [1]\nmu = 0.5\non_slip = \"slide\"\n";
    const Run r = run(nhc_command() + " simulate '" + path + "' -o '" + dir + "/spin.csv'", dir);
    REQUIRE(r.exit_code == 0);
    const double k = 5.0, mu = 0.5, inertia = kM * kR * kR / 2, ts = 3 * mu * kM * kG * kR / (2 * k);
    const std::string events = read_file(dir + "/spin.events.csv");
    REQUIRE(events.rfind("name,t\nfloor.slip,", 0) == 0);
    CHECK(std::abs(std::stod(events.substr(std::string("name,t\nfloor.slip,").size())) - ts) < 1e-8);
    auto c = csv_columns(read_file(dir + "/spin.csv"));
    const double vs = k * ts * ts / (3 * kM * kR);  // x' = r th' at the slip
    for (std::size_t i = 0; i < c["t"].size(); ++i) {
      const double t = c["t"][i];
      if (t <= ts + 1e-8) {  // the last rolling row is the slip point
        CHECK(c["floor.state"][i] == 1);
        CHECK(std::abs(c["x'"][i] - k * t * t / (3 * kM * kR)) < 1e-8);
      } else {
        CHECK(c["floor.state"][i] == 0);
        CHECK(std::abs(c["floor.tangential"][i] - mu * kM * kG) < 1e-9);
        // The slip speed grows from 0 as (t - ts)^2 here: the Coulomb force, with |f| evaluated as
        // sqrt(f.f + 1e-14), reaches mu m g after about 1e-4 s, which leaves 1.7e-6 in x'
        // (docs/contacts.md, "Sliding").
        CHECK(std::abs(c["x'"][i] - (vs + mu * kG * (t - ts))) < 3e-6);
        CHECK(std::abs(c["th'"][i] - (vs / kR + (k * (t * t - ts * ts) / 2 - mu * kM * kG * kR * (t - ts)) / inertia)) <
              3e-5);
      }
    }
  }
  SECTION("bad [contacts]: exit 2 at FILE:LINE:COLUMN") {
    const auto refused = [&](const std::string& contact, const std::string& where, const std::string& message) {
      const std::string scene = incline(dir, contact);
      const Run r = run(nhc_command() + " simulate '" + scene + "' -o '" + dir + "/bad.csv'", dir);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find("incline.toml:" + where) != std::string::npos);
      CHECK(r.err.find(message) != std::string::npos);
      CHECK(!file_exists(dir + "/bad.csv"));
    };
    refused("[contacts.floor]\nnormal = \"lambda1\"\nrolling = [3]\nmu = 0.3\n",
            "22:12:", "rolling constraint 3 is not one of the scene's 2 constraints");
    refused("[contacts.floor]\nnormal = \"lambda1\"\nrolling = [2]\nmu = 0.3\non_slip = \"skid\"\n",
            "24:11:", "on_slip 'skid': stop or slide");
    refused("[contacts.floor]\nnormal = \"lambda1\"\nrolling = [2]\nmu = -1\n", "23:6:", "mu must not be negative");
    refused("[contacts.floor]\nnormal = \"lambda1 +\"\nrolling = [2]\nmu = 0.3\n",
            "21:", "normal force of contact 'floor'");
    refused("[contacts.floor]\nnormal = \"lambda1\"\nrolling = [2]\nsize = 1\nmu = 0.3\n",
            "23:1:", "unknown key 'size'");
  }
}
