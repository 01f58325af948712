// The malformed-scene corpus (tests/bad/) through every subcommand that writes a file:
// `derive -o`, `analyze -o`, `generate -o DIR`, `simulate -o FILE`. Each case must end with
// exit code 2, nothing on standard output, exactly one line `FILE:LINE:COLUMN: error: …` on
// standard error (the position from the case's first line `# expect: LINE:COLUMN`; for
// the empty file, 1:1), no output file, no temporary file and no cache entry.
#include <catch2/catch.hpp>
#include <dirent.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "command_runner.hpp"

namespace {

using nhc::test::file_exists;
using nhc::test::nhc_command;
using nhc::test::read_file;
using nhc::test::Run;
using nhc::test::run;
using nhc::test::scratch_dir;

std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string n = e->d_name;
      if (n != "." && n != "..") names.push_back(n);
    }
    ::closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

struct BadCase {
  std::string name, path, where;  // where: "PATH:LINE:COLUMN: error: "
};

std::vector<BadCase> bad_cases(const std::string& scratch) {
  const std::string dir = std::string(NHC_SOURCE_DIR) + "/tests/bad";
  const std::regex expect_line(R"(^#\s*expect:\s*(\d+):(\d+)\s*$)");
  std::vector<BadCase> cases;
  for (const std::string& name : entries(dir)) {
    if (name.size() < 5 || name.compare(name.size() - 5, 5, ".toml") != 0) continue;
    const std::string path = dir + "/" + name;
    const std::string text = read_file(path);
    const std::string first = text.substr(0, text.find('\n'));
    std::smatch m;
    INFO("case " << name << " must start with '# expect: LINE:COLUMN'");
    REQUIRE(std::regex_match(first, m, expect_line));
    cases.push_back({name, path, path + ":" + m[1].str() + ":" + m[2].str() + ": error: "});
  }
  // An empty file cannot carry the line: its error is a missing key, at 1:1.
  const std::string empty = scratch + "/scenes/empty.toml";
  std::system(("mkdir -p '" + scratch + "/scenes'").c_str());
  { std::ofstream create(empty); }
  cases.push_back({"empty.toml", empty, empty + ":1:1: error: "});
  return cases;
}

/// Runs `arguments` (with the scene path and the output in place of {SCENE} and {OUT}) on every
/// case; `output` is a file or a directory that must not appear.
void check_every_case(const std::string& subcommand, const std::string& arguments) {
  const std::string dir = scratch_dir("bad_" + subcommand);
  const std::vector<BadCase> cases = bad_cases(dir);
  REQUIRE(cases.size() >= 130);
  const std::string cache = dir + "/cache";
  for (const BadCase& c : cases) {
    INFO("nhc " << subcommand << " on tests/bad/" << c.name);
    const std::string output = dir + "/" + c.name + ".out";
    std::string command = arguments;
    command.replace(command.find("{SCENE}"), 7, "'" + c.path + "'");
    command.replace(command.find("{OUT}"), 5, "'" + output + "'");
    const Run r = run("NHC_CACHE_DIR='" + cache + "' " + nhc_command() + " " + subcommand + " " + command, dir);
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    REQUIRE(!r.err.empty());
    CHECK(r.err.back() == '\n');
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.rfind(c.where, 0) == 0);
    CHECK(r.err.size() > c.where.size() + 1);  // a message follows
    CHECK(!file_exists(output));
    CHECK(!file_exists(cache));
    for (const std::string& leftover : entries(dir)) CHECK(leftover.find(c.name) == std::string::npos);
  }
}

}  // namespace

TEST_CASE("malformed scenes: nhc derive -o writes nothing", "[cli][bad]") {
  check_every_case("derive", "{SCENE} -o {OUT}");
}

TEST_CASE("malformed scenes: nhc analyze -o writes nothing", "[cli][bad]") {
  check_every_case("analyze", "{SCENE} --format json -o {OUT}");
}

TEST_CASE("malformed scenes: nhc generate -o DIR writes nothing", "[cli][bad]") {
  check_every_case("generate", "{SCENE} -o {OUT}");
}

TEST_CASE("malformed scenes: nhc simulate -o writes neither CSV nor cache entry", "[cli][bad]") {
  check_every_case("simulate", "{SCENE} -o {OUT}");
}

TEST_CASE("bad flags of nhc simulate are refused before anything is compiled", "[cli][bad]") {
  const std::string dir = scratch_dir("bad_simulate_flags");
  const std::string cache = dir + "/cache", output = dir + "/out.csv";
  const std::string scene = std::string(NHC_SOURCE_DIR) + "/examples/particle.toml";
  for (const std::string flags : {"--t-end -1", "--t-end 0", "--t-end nan", "--t-end inf", "--rtol -1e-6", "--rtol inf",
                                  "--atol 0", "--atol nan", "--outputs 0", "--outputs 1000000000"}) {
    INFO("nhc simulate " << flags);
    const Run r = run("NHC_CACHE_DIR='" + cache + "' " + nhc_command() + " simulate '" + scene + "' " + flags +
                          " -o '" + output + "'",
                      dir);
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(!file_exists(output));
    CHECK(!file_exists(cache));
  }
}

TEST_CASE("a scene path that is a directory or unreadable exits 2", "[cli][bad]") {
  const std::string dir = scratch_dir("bad_paths");
  for (const std::string& scene : {dir, dir + "/missing.toml"}) {
    INFO("scene " << scene);
    const Run r = run(nhc_command() + " derive '" + scene + "' -o '" + dir + "/out.txt'", dir);
    CHECK(r.exit_code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.rfind(scene + ": error: ", 0) == 0);
    CHECK(!file_exists(dir + "/out.txt"));
  }
}
