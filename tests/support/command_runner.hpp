#pragma once
// Running the real `nhc` binary (or any shell command) from tests, with its output captured.

#include <string>

namespace nhc::test {

struct Run {
  int exit_code = -1;
  std::string out, err;
};

/// The whole content of a file ("" when it cannot be read).
std::string read_file(const std::string& path);
bool file_exists(const std::string& path);
/// A fresh, empty directory under the build tree for one test case's files.
std::string scratch_dir(const std::string& name);
/// Runs `command` (arguments already quoted) with stdout and stderr captured in files of `dir`.
Run run(const std::string& command, const std::string& dir);
/// The nhc executable under test, quoted for the shell (NHC_TEST_EXECUTABLE, when set, names another).
std::string nhc_command();
/// Runs a shell command; returns its exit status (-1 when it could not run or was killed) and
/// appends its stdout and stderr to `output`.
int run_command(const std::string& command, std::string& output);

}  // namespace nhc::test
