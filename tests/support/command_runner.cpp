#include "command_runner.hpp"

#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace nhc::test {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool file_exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

std::string scratch_dir(const std::string& name) {
  // One directory per test case; ctest runs cases in separate processes, possibly in parallel.
  const std::string dir = std::string(NHC_BINARY_DIR) + "/tests/scratch/" + name;
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  return dir;
}

Run run(const std::string& command, const std::string& dir) {
  const std::string out = dir + "/stdout.txt", err = dir + "/stderr.txt";
  const int status = std::system((command + " >'" + out + "' 2>'" + err + "'").c_str());
  Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

// NHC_TEST_EXECUTABLE runs these tests against another build of nhc: scripts/sanitize.sh points
// the Release test binary at the sanitized nhc, which is what these tests exercise, instead of
// compiling the whole test binary under the sanitizers as well.
std::string nhc_command() {
  const char* other = std::getenv("NHC_TEST_EXECUTABLE");
  return std::string("'") + (other && *other ? other : NHC_EXECUTABLE) + "'";
}

int run_command(const std::string& command, std::string& output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace nhc::test
