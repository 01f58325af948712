// Reading has limits (nhc/io/input_file.hpp, docs/safety.md): a scene or an
// --input CSV that is not a regular file (/dev/zero, a directory, a FIFO) or is larger than 64 MB
// is refused in one line naming it, exit 2, before it is read (each run is stopped after 60 s, so
// that reading /dev/zero or waiting on a FIFO fails the test instead of hanging it). And the
// CSV messages of item 11: a UTF-8 byte order mark, a duplicate column, control characters
// (never echoed raw), "+1", --columns x,x and --columns t, the time spent reading inputs.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "command_runner.hpp"
#include "nhc/io/shell.hpp"

namespace {

namespace fs = std::filesystem;
using nhc::shell_quote;
using nhc::test::read_file;
using nhc::test::Run;

const std::string kScene = std::string(NHC_SOURCE_DIR) + "/tests/cli/scenes/driven_oscillator.toml";

struct Fixture {
  explicit Fixture(const std::string& name) : dir(nhc::test::scratch_dir(name)) {}
  std::string dir;  // one per test case: ctest runs them in parallel
  Run nhc(const std::string& args) const {
    return nhc::test::run("cd " + shell_quote(dir) + " && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                              "/tests/cli/nhc-cache' timeout 60 " + nhc::test::nhc_command() + " " + args,
                          dir);
  }
  std::string path(const std::string& name) const { return dir + "/" + name; }
};

/// exit 2 and one line on standard error that starts with `start`.
void expect_refused(const Run& r, const std::string& start) {
  INFO(r.out << r.err);
  CHECK(r.exit_code == 2);
  CHECK(r.err.rfind(start, 0) == 0);
  CHECK(r.err.find('\n') == r.err.size() - 1);
}

}  // namespace

TEST_CASE("a scene or an --input file that is not a regular file, or larger than 64 MB, is refused unread",
          "[cli][safety]") {
  const Fixture f("reading_limits");
  REQUIRE(::mkfifo(f.path("fifo").c_str(), 0666) == 0);
  fs::create_directory(f.path("dir"));
  for (const char* name : {"big.toml", "big.csv"}) {  // 65 MB without writing them: sparse files
    std::ofstream(f.path(name)).close();
    REQUIRE(::truncate(f.path(name).c_str(), 65 << 20) == 0);
  }

  expect_refused(f.nhc("simulate /dev/zero"), "/dev/zero: error: is a character device, not a scene file");
  expect_refused(f.nhc("simulate dir"), "dir: error: is a directory, not a scene file");
  expect_refused(f.nhc("simulate fifo"), "fifo: error: is a FIFO, not a scene file");
  expect_refused(f.nhc("derive big.toml"), "big.toml: error: is 65 MB, more than the 64 MB nhc reads as a scene file");

  const std::string run = "simulate " + shell_quote(kScene) + " --input F=@";
  expect_refused(f.nhc(run + "/dev/zero"), "/dev/zero: error: is a character device, not a CSV file");
  expect_refused(f.nhc(run + "/etc"), "/etc: error: is a directory, not a CSV file");
  expect_refused(f.nhc(run + "fifo"), "fifo: error: is a FIFO, not a CSV file");
  expect_refused(f.nhc(run + "big.csv"), "big.csv: error: is 65 MB, more than the 64 MB nhc reads as a CSV file");
}

TEST_CASE("CSV messages of --input and --columns say precisely what is wrong", "[cli][safety]") {
  const Fixture f("csv_messages");
  const std::string run = "simulate " + shell_quote(kScene) + " --input F=@";
  SECTION("a UTF-8 byte order mark and '+1' are read") {
    std::ofstream(f.path("bom.csv")) << "\xEF\xBB\xBFt,F\n0,+1\n3,+1\n";
    const Run r = f.nhc(run + "bom.csv -o out.csv");
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(read_file(f.path("out.csv")).find("\n3,") != std::string::npos);
    // The summary times reading the inputs apart from deriving.
    CHECK(r.out.find(", read inputs ") != std::string::npos);
  }
  SECTION("a duplicate column is named as one") {
    std::ofstream(f.path("dup.csv")) << "t,F,t\n0,1,0\n3,1,3\n";
    expect_refused(f.nhc(run + "dup.csv"), "dup.csv:1:5: error: duplicate column 't' (also column 1)");
  }
  SECTION("control characters are escaped, never echoed") {
    std::ofstream(f.path("nul.csv")) << "t,F\n0,1" << std::string(1, '\0') << "\x1b[31m\n3,1\n";
    expect_refused(f.nhc(run + "nul.csv"), "nul.csv:2:3: error: '1\\x00\\x1b[31m' is not a finite number");
  }
  SECTION("--columns x,x is refused; --columns t writes t alone") {
    expect_refused(f.nhc("simulate " + shell_quote(kScene) + " --columns x,x -o c.csv"),
                   "--columns: error: --columns x,x: column 'x' is named twice");
    const Run r = f.nhc("simulate " + shell_quote(kScene) + " --columns t -o t.csv");
    CHECK(r.exit_code == 0);
    CHECK(read_file(f.path("t.csv")).rfind("t\n0\n0.015\n", 0) == 0);
  }
}
