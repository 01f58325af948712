// Text read from files never becomes code (docs/safety.md): an ensemble file
// whose every string (scene, model and scene-file attributes, design variable names, state and
// invariant names) and file and directory names holding backquotes, $(...), newlines, quotes,
// a gnuplot macro and a trailing backslash go through every plot path — nhc plot,
// ensemble --plot, simulate --plot, compare, linearize --sweep — and the kept scripts are run
// again by gnuplot. Each piece of text would `touch "$NHC_MARK"` if a shell or gnuplot ran it:
// the marker must not exist afterwards, and the pictures must be written.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.hpp"
#include "nhc/io/shell.hpp"

namespace {

namespace fs = std::filesystem;
using nhc::shell_quote;
using nhc::test::file_exists;
using nhc::test::Run;

/// Runs "$NHC_MARK" as a command through a shell, through gnuplot's backquotes and its macros.
const std::string kHostile = "h`touch \"$NHC_MARK\"`$(touch \"$NHC_MARK\");\"'\n@h x\\";

struct Fixture {
  std::string dir = nhc::test::scratch_dir("untrusted_text");
  std::string marker = dir + "/MARKER";

  Run nhc(const std::string& args) const {
    return nhc::test::run("cd " + shell_quote(dir) + " && NHC_MARK=" + shell_quote(marker) + " NHC_CACHE_DIR='" +
                              NHC_BINARY_DIR + "/tests/cli/nhc-cache' " + nhc::test::nhc_command() + " " + args,
                          dir);
  }
  /// No marker, and no temporary file left anywhere under the scratch directory.
  void check_clean() const {
    CHECK_FALSE(file_exists(marker));
    for (const auto& e : fs::recursive_directory_iterator(dir))
      CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
  }
  /// gnuplot itself on the kept script (what a user does to redraw): still runs nothing.
  void redraw(const fs::path& script) const {
    const Run r =
        nhc::test::run("cd " + shell_quote(script.parent_path().string()) + " && NHC_MARK=" + shell_quote(marker) +
                           " gnuplot " + shell_quote("./" + script.filename().string()),
                       dir);
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK_FALSE(file_exists(marker));
  }
};

std::vector<fs::path> files_ending(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ext) found.push_back(e.path());
  return found;
}

}  // namespace

TEST_CASE("an ensemble file and file names with shell and gnuplot syntax in every string run nothing",
          "[cli][plots][safety]") {
  if (std::system("command -v gnuplot > /dev/null && /usr/bin/python3 -c 'import h5py' 2> /dev/null") != 0) {
    WARN("skipped: needs gnuplot and python3-h5py (scripts/setup.sh installs both)");
    return;
  }
  const Fixture f;
  const std::string particle = std::string(NHC_SOURCE_DIR) + "/examples/particle.toml";
  const Run made = f.nhc("ensemble " + shell_quote(particle) + " --vary \"q1'(0)=1:2:4\" -o plain.h5");
  REQUIRE(made.exit_code == 0);
  const std::string hostile_h5 = kHostile + ".h5";
  REQUIRE(std::system(("/usr/bin/python3 " + shell_quote(std::string(NHC_SOURCE_DIR) + "/tests/cli/hostile_h5.py") +
                       " " + shell_quote(f.dir + "/plain.h5") + " " + shell_quote(f.dir + "/" + hostile_h5) + " " +
                       shell_quote(f.marker))
                          .c_str()) == 0);

  SECTION("nhc plot: the file's strings and its name") {
    const Run r = f.nhc("plot " + shell_quote(hostile_h5) + " t_stop");
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    const std::string stem = f.dir + "/" + kHostile + "_t_stop";
    CHECK(file_exists(stem + ".svg"));
    CHECK(file_exists(stem + ".png"));
    f.check_clean();
    f.redraw(stem + ".gp");
  }
  SECTION("a message naming the file's outcomes is one line, its control characters escaped") {
    const Run r = f.nhc("plot " + shell_quote(hostile_h5) + " nosuch");
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("unknown outcome; this ensemble has t_stop") != std::string::npos);
    CHECK(r.err.find("\\n@q1") != std::string::npos);
    CHECK(r.err.find('\n') == r.err.size() - 1);
    f.check_clean();
  }
  SECTION("nhc plot -o STEM in a directory of such a name") {
    const Run r = f.nhc("plot " + shell_quote(hostile_h5) + " t_stop -o " + shell_quote(kHostile + "/" + kHostile));
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(file_exists(f.dir + "/" + kHostile + "/" + kHostile + ".svg"));
    CHECK(file_exists(f.dir + "/" + kHostile + "/" + kHostile + ".png"));
    f.check_clean();
  }
  SECTION("nhc ensemble --plot into a file of such a name") {
    const Run r = f.nhc("ensemble " + shell_quote(particle) + " --vary \"q1'(0)=1:2:3\" --plot t_stop -o " +
                        shell_quote(kHostile + "-e.h5"));
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(file_exists(f.dir + "/" + kHostile + "-e_t_stop.svg"));
    CHECK(file_exists(f.dir + "/" + kHostile + "-e_t_stop.png"));
    f.check_clean();
  }
  SECTION("simulate --plot, compare and linearize --sweep: a scene file and directories of such names") {
    const std::string scene = kHostile + ".toml";
    fs::copy_file(std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml", f.dir + "/" + scene);
    const Run s = f.nhc("simulate " + shell_quote(scene) + " --plot " + shell_quote(kHostile + "-plots") + " -o " +
                        shell_quote(kHostile + ".csv"));
    INFO(s.out << s.err);
    CHECK(s.exit_code == 0);
    CHECK(files_ending(f.dir + "/" + kHostile + "-plots", ".svg").size() >= 3);
    const Run c =
        f.nhc("compare " + shell_quote(scene) + " --models chetaev,vakonomic -o " + shell_quote(kHostile + "-compare"));
    INFO(c.out << c.err);
    CHECK(c.exit_code == 0);
    CHECK(files_ending(f.dir + "/" + kHostile + "-compare", ".svg").size() >= 3);
    const Run l =
        f.nhc("linearize " + shell_quote(std::string(NHC_SOURCE_DIR) + "/tests/linearize/scenes/rolling_disk.toml") +
              " --at \"ps'=5\" --sweep \"ps'=1:4:4\" -o " + shell_quote(kHostile + "-linearize"));
    INFO(l.out << l.err);
    CHECK(l.exit_code == 0);
    CHECK(file_exists(f.dir + "/" + kHostile + "-linearize/stability.svg"));
    CHECK(file_exists(f.dir + "/" + kHostile + "-linearize/stability.png"));
    f.check_clean();
    for (const fs::path& gp : files_ending(f.dir + "/" + kHostile + "-plots", ".gp")) f.redraw(gp);
  }
}
