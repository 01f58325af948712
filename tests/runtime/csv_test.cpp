// The CSV file: header as in docs/runtime.md, one row per sample, written atomically.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "appell_hamel_fixture.hpp"

using namespace nhc::runtime;

TEST_CASE("CSV header and rows", "[runtime]") {
  const ah_test::AppellHamel ah;
  const Model model = ah_test::model();
  IntegratorOptions o;
  const RunResult run = simulate(model, {}, ah.initial(), output_times(0.0, 0.1, 10), o);
  REQUIRE_FALSE(run.failure.has_value());
  const auto dir = std::filesystem::temp_directory_path() / ("nhc_csv_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "run.csv").string();
  write_csv(path, model, ah.parameters(), run.samples);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  CHECK(header == "t,x,x',x'',y,y',y'',z,z',z'',lambda1,hidden:1,invariant:energy");
  int rows = 0;
  std::string line;
  while (std::getline(in, line)) ++rows;
  CHECK(rows == 11);
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) ++files, (void)entry;
  CHECK(files == 1);  // no temporary file left behind
  std::filesystem::remove_all(dir);
}
