// `nhc generate` through the real binary: files written, flags, exit codes.
#include <catch2/catch.hpp>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Run {
  int status = -1;
  std::string output;  ///< stdout and stderr
};

Run nhc(const std::string& arguments) {
  const std::string command = std::string("'") + NHC_EXECUTABLE + "' " + arguments + " 2>&1";
  Run run;
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  char buffer[4096];
  size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(NHC_BINARY_DIR) / "tests" / "codegen" / "scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

const std::string kAppellHamel = std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml";

}  // namespace

TEST_CASE("nhc generate writes <scene>_<model>.hpp", "[codegen]") {
  const fs::path dir = scratch("command") / "created" / "on" / "demand";
  const Run run = nhc("generate '" + kAppellHamel + "' --model holder --jacobian sparse -o '" + dir.string() + "'");
  INFO(run.output);
  REQUIRE(run.status == 0);
  const fs::path header = dir / "appell_hamel_holder.hpp";
  REQUIRE(fs::exists(header));
  CHECK(run.output.find("appell_hamel_holder.hpp: 7 states, operations ") != std::string::npos);
  const std::string text = read_file(header);
  CHECK(text.find("namespace nhc_gen::appell_hamel_holder {") != std::string::npos);
  CHECK(text.find("inline void jacobian_values(") != std::string::npos);
  CHECK(text.find("inline void jacobian(") == std::string::npos);
  // No temporary file is left behind.
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file() ? 1 : 0;
  CHECK(files == 1);

  const Run none = nhc("generate '" + kAppellHamel + "' --jacobian none --quiet -o '" + dir.string() + "'");
  REQUIRE(none.status == 0);
  CHECK(none.output.empty());
  // Default model: the scene's [simulate] model.
  CHECK(read_file(dir / "appell_hamel_chetaev.hpp").find("inline void jacobian") == std::string::npos);
}

TEST_CASE("nhc generate reports bad input and inapplicable models", "[codegen]") {
  const fs::path dir = scratch("command_errors");
  CHECK(nhc("generate '" + (dir / "missing.toml").string() + "' -o '" + dir.string() + "'").status == 2);
  CHECK(nhc("generate '" + kAppellHamel + "' --jacobian diagonal -o '" + dir.string() + "'").status == 2);
  CHECK(nhc("generate '" + kAppellHamel + "' --model newton -o '" + dir.string() + "'").status == 2);

  // Suslov needs the constraint to contain the dependent coordinate's first derivative.
  const fs::path scene = dir / "no_suslov.toml";
  std::ofstream(scene) << "name = \"no_suslov\"\ncoordinates = [\"x\", \"y\"]\n"
                          "lagrangian = \"(x'^2 + y'^2)/2\"\nconstraints = [\"y'' - x\"]\n"
                          "dependent = [\"y\"]\n";
  const Run run = nhc("generate '" + scene.string() + "' --model suslov -o '" + dir.string() + "'");
  INFO(run.output);
  CHECK(run.status == 3);
  CHECK(!fs::exists(dir / "no_suslov_suslov.hpp"));
}
