// generated/ against a fresh `nhc generate` of every example (staleness), the headers compiled
// warning-free by g++ and clang++ under the strict flags, and the C table they declare
// identical to the runtime's.
#include <catch2/catch.hpp>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "nhc/io/shell.hpp"

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

using nhc::shell_quote;

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A fresh, empty directory under the build tree.
fs::path scratch_directory(const std::string& name) {
  const fs::path dir = fs::path(NHC_BINARY_DIR) / "tests" / "codegen" / "scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<fs::path> files_with_extension(const fs::path& dir, const std::string& extension) {
  std::vector<fs::path> files;
  if (!fs::exists(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == extension) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// The compilers to check with: the one building nhc, g++ and clang++ when installed.
std::vector<std::string> compilers() {
  std::vector<std::string> found;
  for (const std::string c : {"g++", "clang++"})
    if (run("command -v " + c + " > /dev/null 2>&1") == 0) found.push_back(c);
  return found;
}

const char* kStrictFlags = "-std=c++17 -O2 -Wall -Wextra -Wpedantic -Wconversion -Wshadow -Werror";

/// Compiles `source` (written to dir/name) with every compiler; returns the failures' logs.
std::string compile_everywhere(const fs::path& dir, const std::string& name, const std::string& source) {
  const fs::path file = dir / name;
  std::ofstream(file) << source;
  std::string failures;
  for (const std::string& cxx : compilers()) {
    const fs::path log = dir / (name + "." + cxx + ".log");
    const std::string command = cxx + " " + kStrictFlags + " -c " + shell_quote(file.string()) + " -o /dev/null > " +
                                shell_quote(log.string()) + " 2>&1";
    if (run(command) != 0) failures += cxx + " on " + name + ":\n" + read_file(log) + "\n";
  }
  return failures;
}

/// The member list of struct nhc_model_table in `text`, comments and blank space removed.
std::string table_members(const std::string& text) {
  const auto begin = text.find("struct nhc_model_table {");
  REQUIRE(begin != std::string::npos);
  const auto end = text.find("};", begin);
  std::string body = text.substr(begin, end - begin);
  body = std::regex_replace(body, std::regex(R"(/\*[\s\S]*?\*/)"), "");
  body = std::regex_replace(body, std::regex(R"(//[^\n]*)"), "");
  body = std::regex_replace(body, std::regex(R"(\s+)"), " ");
  return body;
}

}  // namespace

TEST_CASE("generated/ is up to date with examples/ (run the `regenerate` target)", "[codegen]") {
  const fs::path source(NHC_SOURCE_DIR);
  const fs::path fresh = scratch_directory("fresh");
  for (const fs::path& scene : files_with_extension(source / "examples", ".toml")) {
    INFO(scene);
    REQUIRE(run(shell_quote(NHC_EXECUTABLE) + " generate " + shell_quote(scene.string()) +
                " --quiet --reduced-form -o " + shell_quote(fresh.string())) == 0);
  }
  std::set<std::string> fresh_names, committed_names;
  for (const fs::path& f : files_with_extension(fresh, ".hpp")) fresh_names.insert(f.filename());
  for (const fs::path& f : files_with_extension(source / "generated", ".hpp")) committed_names.insert(f.filename());
  CHECK(fresh_names == committed_names);
  for (const std::string& name : fresh_names) {
    INFO("generated/" << name << " differs from a fresh `nhc generate`: build the `regenerate` target");
    CHECK(read_file(fresh / name) == read_file(source / "generated" / name));
  }
}

TEST_CASE("generated headers compile warning-free with g++ and clang++", "[codegen]") {
  REQUIRE(!compilers().empty());
  const fs::path dir = scratch_directory("strict");
  const std::vector<fs::path> headers = files_with_extension(fs::path(NHC_SOURCE_DIR) / "generated", ".hpp");
  REQUIRE(!headers.empty());
  std::string failures;
  // Each header of generated/ alone, included twice, with the exported C table.
  for (const fs::path& h : headers) {
    const std::string include = "#include " + std::string("\"") + h.string() + "\"\n";
    failures += compile_everywhere(dir, h.stem().string() + "_export.cpp",
                                   "#define NHC_EXPORT_MODEL_TABLE\n" + include + include);
    // As nhc::jit compiles a splittable header (docs/generated-code.md): each part of two on its
    // own. (The examples' headers are below HeaderOptions::split_from_bytes and carry no parts;
    // tests/jit/split_compile_test.cpp splits a small one on purpose.)
    if (read_file(h).find("NHC_PART") == std::string::npos) continue;
    for (const char* part : {"0", "1"})
      failures += compile_everywhere(dir, h.stem().string() + "_part" + part + ".cpp",
                                     "#define NHC_EXPORT_MODEL_TABLE\n#define NHC_PARTS 2\n#define NHC_PART " +
                                         std::string(part) + "\n" + include);
  }
  // Every header the tests compiled, all of one Jacobian flavour in one translation unit.
  for (const std::string flavour : {"dense", "sparse"}) {
    std::string source;
    for (const fs::path& h : files_with_extension(fs::path(NHC_CODEGEN_HEADER_DIR) / flavour, ".hpp"))
      source += "#include \"" + h.string() + "\"\n";
    REQUIRE(!source.empty());
    failures += compile_everywhere(dir, "all_" + flavour + ".cpp", source);
  }
  INFO(failures);
  CHECK(failures.empty());
}

TEST_CASE("the C table of a generated header is the runtime's", "[codegen]") {
  const std::string runtime_table =
      table_members(read_file(fs::path(NHC_SOURCE_DIR) / "runtime/nhc/runtime/model_table.h"));
  for (const fs::path& h : files_with_extension(fs::path(NHC_SOURCE_DIR) / "generated", ".hpp")) {
    INFO(h);
    CHECK(table_members(read_file(h)) == runtime_table);
  }
}
