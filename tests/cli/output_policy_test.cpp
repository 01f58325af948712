// The one output policy (nhc/io/output_path.hpp, docs/safety.md), in a
// temporary directory: a character device and a FIFO given as -o are written in place and stay
// what they are (a FIFO without a reader is exit 2, not a hang); a symbolic link stays and its
// target gets the CSV; an --input file is refused as -o by identity (by name, through a link,
// and as the CSV that --plot DIR would write), and the scene as linearize's -o DIR or a file in
// it, and as connect's -o; a path under a regular file is exit 2.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
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
  std::string dir = nhc::test::scratch_dir("output_policy");
  /// nhc in the directory, stopped after 60 s so that a hang is a failure, not a stuck test.
  Run nhc(const std::string& args) const {
    return nhc::test::run("cd " + shell_quote(dir) + " && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                              "/tests/cli/nhc-cache' timeout 60 " + nhc::test::nhc_command() + " " + args,
                          dir);
  }
  std::string path(const std::string& name) const { return dir + "/" + name; }
};

mode_t type_of(const std::string& path) {
  struct stat s {};
  REQUIRE(::lstat(path.c_str(), &s) == 0);
  return s.st_mode & S_IFMT;
}

}  // namespace

TEST_CASE("outputs: a device and a FIFO are written in place, a link's target is replaced, inputs are refused",
          "[cli][safety]") {
  const Fixture f;
  SECTION("a character device (mknod c 1 3, the null device) stays a device") {
    if (::mknod(f.path("null").c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
      WARN("skipped: mknod is not permitted here (needs root or CAP_MKNOD)");
      return;
    }
    const Run r = f.nhc("simulate " + shell_quote(kScene) + " -o null");
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(type_of(f.path("null")) == S_IFCHR);
  }
  SECTION("a FIFO: written to its reader; without one, exit 2 at once; never replaced") {
    REQUIRE(::mkfifo(f.path("fifo").c_str(), 0666) == 0);
    Run r = f.nhc("simulate " + shell_quote(kScene) + " -o fifo");
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("fifo: error: the output fifo is a FIFO that nobody reads") != std::string::npos);
    CHECK(type_of(f.path("fifo")) == S_IFIFO);
    // A reader started first gets the whole CSV.
    r = nhc::test::run("cd " + shell_quote(f.dir) +
                           " && (timeout 60 cat fifo > read.csv &) && sleep 0.2 && NHC_CACHE_DIR='" + NHC_BINARY_DIR +
                           "/tests/cli/nhc-cache' timeout 60 " + nhc::test::nhc_command() + " simulate " +
                           shell_quote(kScene) + " -o fifo && wait",
                       f.dir);
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(type_of(f.path("fifo")) == S_IFIFO);
    for (int k = 0; k < 100 && read_file(f.path("read.csv")).size() < 1000; ++k) ::usleep(50000);
    CHECK(read_file(f.path("read.csv")).rfind("t,x,x',x'',input:F\n0,0,0,0,0\n", 0) == 0);
  }
  SECTION("a symbolic link stays; its target gets the CSV") {
    std::ofstream(f.path("target.csv")) << "old\n";
    fs::create_symlink("target.csv", f.path("latest.csv"));
    for (const std::string command : {"simulate", "derive"}) {
      INFO(command);
      const Run r = f.nhc(command + " " + shell_quote(kScene) + " -o latest.csv");
      INFO(r.out << r.err);
      CHECK(r.exit_code == 0);
      CHECK(type_of(f.path("latest.csv")) == S_IFLNK);
      CHECK(read_file(f.path("target.csv")) != "old\n");
      CHECK(read_file(f.path("target.csv")) == read_file(f.path("latest.csv")));
    }
  }
  SECTION("an --input file is refused as an output by identity, and left as it was") {
    {
      std::ofstream in(f.path("F.csv"));
      in << "t,F\n";
      for (int k = 0; k <= 30; ++k) in << k * 0.1 << ",0.5\n";
    }
    const std::string before = read_file(f.path("F.csv"));
    fs::create_symlink("F.csv", f.path("F-link.csv"));
    fs::create_directory(f.path("plots"));
    fs::copy_file(f.path("F.csv"), f.path("plots/driven_oscillator_chetaev.csv"));
    const std::string in_plots = read_file(f.path("plots/driven_oscillator_chetaev.csv"));
    for (const auto& [input, output] : {std::pair<std::string, std::string>{"F.csv", "-o F.csv"},
                                        {"F.csv", "-o ./F-link.csv"},
                                        {"plots/driven_oscillator_chetaev.csv", "--plot plots"}}) {
      INFO(output);
      const Run r = f.nhc("simulate " + shell_quote(kScene) + " --input F=@" + input + " " + output);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find("is the input " + input + " (the same file)") != std::string::npos);
    }
    CHECK(read_file(f.path("F.csv")) == before);
    CHECK(read_file(f.path("plots/driven_oscillator_chetaev.csv")) == in_plots);
  }
  SECTION("linearize -o and connect -o refuse the scene (linearize replaced it with its directory)") {
    std::ofstream(f.path("scene.toml")) << read_file(kScene);
    fs::create_directory(f.path("lin"));
    fs::create_symlink("../scene.toml", f.path("lin/A.csv"));
    for (const std::string& args :
         {std::string("linearize scene.toml -o scene.toml"), std::string("linearize scene.toml -o lin"),
          std::string("connect scene.toml --to x=1 --t-end 1 -o scene.toml")}) {
      INFO(args);
      const Run r = f.nhc(args);
      CHECK(r.exit_code == 2);
      CHECK(r.err.find("is the input scene.toml (the same file)") != std::string::npos);
      CHECK(read_file(f.path("scene.toml")) == read_file(kScene));
    }
  }
  SECTION("a path under a regular file is bad input (exit 2), not the environment") {
    std::ofstream(f.path("scene.toml")) << read_file(kScene);
    const Run r = f.nhc("simulate scene.toml -o scene.toml/x.csv");
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("scene.toml is a file, not a directory, so the output scene.toml/x.csv cannot be created") !=
          std::string::npos);
  }
}

// The check holds a stream output open from the start (nhc/io/output_path.hpp), so a FIFO nobody
// reads is refused before the work: optimize prints nothing of its solve (its first line comes
// after the check) and simulate derives nothing (its scene cache, empty at the start, stays empty).
// Both under `timeout 60`: a hang fails the test instead of stopping the suite.
TEST_CASE("outputs: a FIFO without a reader is refused before the command's work", "[cli][safety]") {
  const Fixture f;
  REQUIRE(::mkfifo(f.path("fifo").c_str(), 0666) == 0);
  const std::string cache = f.path("cache");
  const auto run = [&](const std::string& args) {
    return nhc::test::run("cd " + shell_quote(f.dir) + " && NHC_CACHE_DIR=" + shell_quote(cache) + " timeout 60 " +
                              nhc::test::nhc_command() + " " + args,
                          f.dir);
  };
  SECTION("optimize: the snakeboard at 160 intervals (seconds of IPOPT) is never started") {
    const Run r = run("optimize " + shell_quote(std::string(NHC_SOURCE_DIR) + "/examples/snakeboard_move.toml") +
                      " --intervals 160 -o fifo");
    INFO(r.out << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("fifo: error: the output fifo is a FIFO that nobody reads") != std::string::npos);
    CHECK(r.out.empty());
    CHECK(r.err.find("iteration") == std::string::npos);
  }
  SECTION("simulate: nothing is derived") {
    const Run r =
        run("simulate " + shell_quote(std::string(NHC_SOURCE_DIR) + "/examples/tumbling_top_quaternion.toml") +
            " --t-end 2000 --outputs 100000 -o fifo");
    INFO(r.out << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("fifo: error: the output fifo is a FIFO that nobody reads") != std::string::npos);
    CHECK(r.out.empty());
    CHECK(!fs::exists(cache + "/scenes"));
  }
  SECTION("optimize with a reader started first: the reader, held open through the solve, gets the whole CSV") {
    const Run r = nhc::test::run("cd " + shell_quote(f.dir) +
                                     " && (timeout 60 cat fifo > read.csv &) && sleep 0.2 && NHC_CACHE_DIR=" +
                                     shell_quote(cache) + " timeout 60 " + nhc::test::nhc_command() + " optimize " +
                                     shell_quote(std::string(NHC_SOURCE_DIR) + "/examples/heisenberg_optimal.toml") +
                                     " --intervals 10 -o fifo && wait",
                                 f.dir);
    INFO(r.out << r.err);
    CHECK(r.exit_code == 0);
    CHECK(type_of(f.path("fifo")) == S_IFIFO);
    for (int k = 0; k < 100 && read_file(f.path("read.csv")).find("\n1,") == std::string::npos; ++k) ::usleep(50000);
    const std::string csv = read_file(f.path("read.csv"));
    CHECK(csv.rfind("t,x,x',y,y',z,z'\n", 0) == 0);
    CHECK(csv.find("\n1,") != std::string::npos);  // the last row, at t_end = 1
  }
}
