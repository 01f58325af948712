// The building blocks of fault tolerance in-process: AtomicDirectory, the same-file check of outputs,
// SHA-256 (FIPS 180-2 test vectors) and the compiler's time limit in run_process.
#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/tools/sha256.hpp"
#include "nhc/tools/subprocess.hpp"

namespace fs = std::filesystem;

namespace {

/// A fresh empty directory under the build tree, removed at the end of the test.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name)
      : dir(fs::path(NHC_BINARY_DIR) / "tests" / "faults" / ("scratch_" + name + "_" + std::to_string(getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
};

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string read(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The entries of `dir` (names), sorted.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("AtomicDirectory: a new directory appears whole at commit, with nothing beside it", "[faults]") {
  Scratch s("new");
  const fs::path target = s.dir / "a" / "b" / "report";
  {
    nhc::AtomicDirectory dir(target.string());
    nhc::write_file_atomically(dir.file("one.txt"), [](std::ostream& out) { out << "1"; });
    nhc::write_file_atomically(dir.file("two.txt"), [](std::ostream& out) { out << "2"; });
    CHECK_FALSE(fs::exists(target));
    dir.commit();
  }
  CHECK(names_in(target) == std::vector<std::string>{"one.txt", "two.txt"});
  CHECK(names_in(target.parent_path()) == std::vector<std::string>{"report"});
}

TEST_CASE("AtomicDirectory: a failure leaves nothing new, not even the parents it created", "[faults]") {
  Scratch s("failure");
  const fs::path target = s.dir / "new_parent" / "report";
  try {
    nhc::AtomicDirectory dir(target.string());
    nhc::write_file_atomically(dir.file("one.txt"), [](std::ostream& out) { out << "1"; });
    throw std::runtime_error("the measurement failed");
  } catch (const std::runtime_error&) {
  }
  CHECK(names_in(s.dir).empty());
}

TEST_CASE("AtomicDirectory: an existing directory is untouched on failure, updated file by file on commit",
          "[faults]") {
  Scratch s("existing");
  const fs::path target = s.dir / "report";
  fs::create_directories(target);
  write(target / "report.md", "old");
  write(target / "notes.txt", "the user's");
  try {
    nhc::AtomicDirectory dir(target.string());
    write(dir.file("report.md"), "new");
    throw std::runtime_error("disk full");
  } catch (const std::runtime_error&) {
  }
  CHECK(read(target / "report.md") == "old");
  CHECK(names_in(s.dir) == std::vector<std::string>{"report"});
  {
    nhc::AtomicDirectory dir(target.string());
    write(dir.file("report.md"), "new");
    dir.commit();
  }
  CHECK(read(target / "report.md") == "new");
  CHECK(read(target / "notes.txt") == "the user's");
  CHECK(names_in(s.dir) == std::vector<std::string>{"report"});
}

TEST_CASE("AtomicDirectory: never replaces an input, inside the directory or as the directory", "[faults]") {
  Scratch s("inputs");
  const fs::path target = s.dir / "out";
  fs::create_directories(target);
  write(target / "report.md", "the user's scene, oddly named");
  const std::string input = (target / "report.md").string();
  {
    nhc::AtomicDirectory dir(target.string(), {input});
    write(dir.file("workprec.csv"), "x");
    write(dir.file("report.md"), "y");
    CHECK_THROWS_AS(dir.commit(), nhc::InputError);
  }
  CHECK(read(target / "report.md") == "the user's scene, oddly named");
  CHECK(names_in(target) == std::vector<std::string>{"report.md"});  // nothing moved at all
  CHECK_THROWS_AS(nhc::AtomicDirectory(input, {input}), nhc::InputError);
}

TEST_CASE("same_file: names, symbolic links and hard links of one file", "[faults]") {
  Scratch s("same");
  const fs::path a = s.dir / "a.toml";
  write(a, "x");
  fs::create_symlink(a, s.dir / "link");
  fs::create_hard_link(a, s.dir / "hard");
  fs::create_directories(s.dir / "sub");
  CHECK(nhc::same_file(a.string(), (s.dir / "sub" / ".." / "a.toml").string()));
  CHECK(nhc::same_file(a.string(), (s.dir / "link").string()));
  CHECK(nhc::same_file(a.string(), (s.dir / "hard").string()));
  CHECK_FALSE(nhc::same_file(a.string(), (s.dir / "b.toml").string()));
  write(s.dir / "c.toml", "x");
  CHECK_FALSE(nhc::same_file(a.string(), (s.dir / "c.toml").string()));  // equal bytes, another file
  try {
    nhc::check_output_file((s.dir / "hard").string(), {a.string()});
    FAIL("an output that is the input was accepted");
  } catch (const nhc::InputError& e) {
    CHECK(std::string(e.what()).find((s.dir / "hard").string()) != std::string::npos);
    CHECK(std::string(e.what()).find(a.string()) != std::string::npos);
  }
  CHECK_THROWS_AS(nhc::check_output_file((s.dir / "sub").string(), {}), nhc::InputError);
}

TEST_CASE("write_file_atomically: an unwritable place is an EnvironmentError naming the path", "[faults]") {
  try {
    nhc::write_file_atomically("/proc/nhc-cannot-write-here.csv", [](std::ostream& out) { out << "x"; });
    FAIL("writing into /proc succeeded");
  } catch (const nhc::EnvironmentError& e) {
    CHECK(std::string(e.what()).find("/proc/nhc-cannot-write-here.csv") != std::string::npos);
  }
}

TEST_CASE("sha256: the FIPS 180-2 test vectors", "[faults]") {
  CHECK(nhc::tools::sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(nhc::tools::sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(nhc::tools::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  Scratch s("sha");
  write(s.dir / "f", "abc");
  CHECK(nhc::tools::sha256_file_hex(s.dir / "f") == nhc::tools::sha256_hex("abc"));
  CHECK_FALSE(nhc::tools::sha256_file_hex(s.dir / "missing"));
}

TEST_CASE("run_process: a time limit stops the whole process group, a missing program says why", "[faults]") {
  std::string output;
  const auto start = std::chrono::steady_clock::now();
  const nhc::tools::ProcessResult r = nhc::tools::run_process({"sh", "-c", "sleep 30 & sleep 30"}, output, 0.3);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(r.started);
  CHECK(r.timed_out);
  CHECK_FALSE(r.ok());
  CHECK(seconds < 5);
  const nhc::tools::ProcessResult quick = nhc::tools::run_process({"sh", "-c", "echo hi; exit 3"}, output, 10);
  CHECK(quick.exit_status == 3);
  CHECK_FALSE(quick.timed_out);
  CHECK(output == "hi\n");
  const nhc::tools::ProcessResult missing = nhc::tools::run_process({"/nonexistent/compiler"}, output, 10);
  CHECK_FALSE(missing.started);
  CHECK(missing.start_error == "No such file or directory");
}
