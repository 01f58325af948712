// `nhc simulate --integrator variational --step H` (docs/variational.md) as a user meets
// it: the inclined knife edge against its closed form ([reference]) with IDA's CSV columns; the
// refusals of flags and scenes the integrator does not take (exit 2, nothing written); Newton's
// failure at the Appell–Hamel singular point in words (exit 3, the motion up to there kept).
#include <catch2/catch.hpp>

#include <fstream>
#include <regex>
#include <string>

#include "command_runner.hpp"

namespace {

using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::run;
using nhc::test::Run;
using nhc::test::scratch_dir;

std::string example(const std::string& name) { return "'" + std::string(NHC_SOURCE_DIR) + "/examples/" + name + "'"; }

/// The number after `label` in `text`; NaN when absent.
double number_after(const std::string& text, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(label + " ([-+0-9.eE]+)"))) return std::nan("");
  return std::stod(m[1]);
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

TEST_CASE("nhc simulate --integrator variational: the inclined knife edge, IDA's columns", "[cli][variational]") {
  const std::string dir = scratch_dir("variational_knife");
  const Run ida =
      run(nhc_command() + " simulate " + example("knife_edge_incline.toml") + " -o '" + dir + "/ida.csv'", dir);
  REQUIRE(ida.exit_code == 0);
  const std::string flags = " --integrator variational --step ";
  const Run coarse = run(
      nhc_command() + " simulate " + example("knife_edge_incline.toml") + flags + "0.01 -o '" + dir + "/coarse.csv'",
      dir);
  const Run fine =
      run(nhc_command() + " simulate " + example("knife_edge_incline.toml") + flags + "0.005 -o '" + dir + "/fine.csv'",
          dir);
  INFO(coarse.out << coarse.err);
  REQUIRE(coarse.exit_code == 0);
  REQUIRE(fine.exit_code == 0);
  CHECK(coarse.out.find("variational integrator") != std::string::npos);
  // The same columns as IDA's run, as many rows.
  const std::string ida_csv = read_file(dir + "/ida.csv"), csv = read_file(dir + "/coarse.csv");
  CHECK(first_line(csv) == first_line(ida_csv));
  CHECK(std::count(csv.begin(), csv.end(), '\n') == std::count(ida_csv.begin(), ida_csv.end(), '\n'));
  // The error against [reference] falls with h² (x = g sin α sin²(wt)/(2w²), …).
  const double e_coarse = number_after(coarse.out, "max reference error"),
               e_fine = number_after(fine.out, "max reference error");
  CHECK(e_coarse / e_fine == Approx(4.0).epsilon(0.1));
  CHECK(number_after(coarse.out, "max discrete-constraint residual") < 1e-12);
}

TEST_CASE("nhc simulate --integrator variational: refusals name the flag or the scene, exit 2", "[cli][variational]") {
  const std::string dir = scratch_dir("variational_refusals");
  const std::string out = " -o '" + dir + "/run.csv'";
  struct Refusal {
    std::string arguments, words;
  };
  const std::vector<Refusal> refusals = {
      {example("knife_edge.toml") + " --step 0.01", "--step is the fixed step of --integrator variational"},
      {example("knife_edge.toml") + " --integrator variational", "needs --step H"},
      {example("knife_edge.toml") + " --integrator variational --step 0", "--step"},
      {example("knife_edge_incline.toml") + " --model vakonomic --integrator variational --step 0.01",
       "takes the chetaev model, not vakonomic"},
      {example("knife_edge.toml") + " --integrator variational --step 0.01 --project", "--project applies to IDA"},
      {example("knife_edge.toml") + " --integrator variational --step 1e-9 --t-end 10", "more than --max-steps"},
      {example("knife_edge_incline.toml") + " --integrator variational --step 0.01 --sensitivity alpha",
       "does not go with --integrator variational"},
      {example("particle_spring.toml") + " --integrator variational --step 0.01", "has order 2"},
      {example("knife_edge.toml") + " --integrator rk4 --step 0.01", "--integrator"},
      {example("knife_edge.toml") + " --integrator variational --step 9.99 --t-end 10",
       "--step 9.99 does not fit the run"},
  };
  for (const Refusal& r : refusals) {
    const Run result = run(nhc_command() + " simulate " + r.arguments + out, dir);
    INFO(r.arguments << "\n" << result.err);
    CHECK(result.exit_code == 2);
    CHECK(result.err.find(r.words) != std::string::npos);
    CHECK(std::count(result.err.begin(), result.err.end(), '\n') == 1);
    CHECK_FALSE(file_exists(dir + "/run.csv"));
  }
}

TEST_CASE("nhc simulate --integrator variational: a scene too large for the dense Newton matrix is refused",
          "[cli][variational]") {
  // 201 coordinates and 200 constraints: 401 unknowns per step, one more than the limit.
  const std::string dir = scratch_dir("variational_size");
  std::string coordinates, lagrangian, constraints;
  for (int i = 0; i <= 200; ++i) {
    coordinates += (i ? ", \"q" : "\"q") + std::to_string(i) + "\"";
    lagrangian += (i ? " + q" : "q") + std::to_string(i) + "'^2/2";
    if (i < 200) constraints += (i ? ", \"q" : "\"q") + std::to_string(i) + "' - q" + std::to_string(i + 1) + "'\"";
  }
  const std::string scene = dir + "/large.toml";
  {
    std::ofstream out(scene);
    out << "name = \"large\"\ncoordinates = [" << coordinates << "]\nlagrangian = \"" << lagrangian
        << "\"\nconstraints = [" << constraints << "]\n";
  }
  const Run r = run(
      nhc_command() + " simulate '" + scene + "' --integrator variational --step 0.01 -o '" + dir + "/run.csv'", dir);
  INFO(r.err);
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("401 coordinates and multipliers, more than the 400") != std::string::npos);
  CHECK_FALSE(file_exists(dir + "/run.csv"));
}

TEST_CASE("nhc simulate --integrator variational: Newton's failure in words, the motion up to it kept",
          "[cli][variational]") {
  // Appell–Hamel: the horizontal speed reaches 0 at t* = v0 (a² + b²)/(g a b), where the constraint
  // gradient is singular (models.md); the steps cannot pass it.
  const std::string dir = scratch_dir("variational_newton");
  const Run r = run(nhc_command() + " simulate " + example("appell_hamel.toml") +
                        " --integrator variational --step 0.01 --t-end 10 -o '" + dir + "/run.csv'",
                    dir);
  INFO(r.out << r.err);
  CHECK(r.exit_code == 3);
  CHECK(std::regex_search(r.err, std::regex("Newton's method did not converge on the variational step [0-9]+ from t = "
                                            "[0-9.]+ to [0-9.]+ \\(step h = 0.01, 20 iterations")));
  CHECK(r.err.find("try a smaller step (--step)") != std::string::npos);
  CHECK(r.out.find("the motion up to the failure") != std::string::npos);
  CHECK(file_exists(dir + "/run.csv"));
}

TEST_CASE("nhc simulate --integrator variational: a run ends on t_end, before a singular point after it",
          "[cli][variational]") {
  const std::string dir = scratch_dir("variational_ends_on_t_end");
  // Appell–Hamel's chetaev motion reaches v = 0, where the constraint is singular, at
  // t* = v0 (a² + b²)/(g a b) = sqrt(1.25)·1.25/(9.81·0.5) = 0.28492: a run to 0.284 with step 0.01 ends
  // there (29 steps of 0.284/29) instead of stepping to 0.30 beyond t*.
  const Run r = run(nhc_command() + " simulate " + example("appell_hamel.toml") +
                        " --integrator variational --step 0.01 --t-end 0.284 --outputs 4 -o -",
                    dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const std::string last = r.out.substr(r.out.rfind('\n', r.out.size() - 2) + 1);
  CHECK(last.rfind("0.284,", 0) == 0);
  CHECK(run(nhc_command() + " simulate " + example("appell_hamel.toml") + " --t-end 0.284 -o -", dir).exit_code == 0);
}
