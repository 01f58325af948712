// nhc — the command a user runs: starts the nhc program (nhc-main) with address randomization
// off, so that every run of one scene writes the same code (fixed_address_layout.hpp says why),
// and with the C library's heap in transparent huge pages where the user has not chosen
// otherwise (heap_in_huge_pages below says why).
//
// nhc-main could do this itself by executing itself once more (it does, when started directly),
// but by then it has loaded some thirty shared libraries (GiNaC, SUNDIALS, OpenSSL, fmt),
// 45 ms on the 2-core CI machine, a tenth of `nhc generate` on the Whipple bicycle. This launcher
// needs only the C library. Exit 4 (environment) when nhc-main cannot be found or started.
#include <sys/personality.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "command_programs.hpp"
#include "exit_codes.hpp"

namespace {

/// Asks the C library (glibc ≥ 2.35; older ones ignore it) to back the heap with transparent
/// huge pages, through the GLIBC_TUNABLES that nhc-main and the compilers it starts read at
/// startup. The symbolic core allocates tens of megabytes in small pieces; in 4 kB pages each
/// first touch is a page fault, and on the 2-core CI machine (a virtual machine, where faults are
/// dear) `nhc generate` of the Whipple bicycle spent about a seventh of its time in them (5,374
/// faults, 412 ms task-clock; 1,878 and 347 ms with huge pages, perf stat -r 10). A user's own
/// glibc.malloc.hugetlb setting is kept, and under a limit on address space (ulimit -v) the heap
/// stays in small pages: huge pages round each of its extensions up to 2 MB of that space, and a
/// limit that left room for nhc's libraries' static initializers would no longer.
void heap_in_huge_pages() {
  rlimit address_space{};
  if (getrlimit(RLIMIT_AS, &address_space) != 0 || address_space.rlim_cur != RLIM_INFINITY) return;
  const char* current = std::getenv("GLIBC_TUNABLES");
  std::string tunables = current ? current : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;
  tunables += tunables.empty() ? "glibc.malloc.hugetlb=1" : ":glibc.malloc.hugetlb=1";
  setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
}

/// The address space (ulimit -v) nhc-main needs before its own code runs: its shared libraries'
/// mappings and their static initializers took about 40 MB on the 2-core CI machine. Below that
/// the loader fails (exit 127) or an initializer's allocation does, which aborts the process
/// before main can say anything (exit 134, "terminate called without an active exception" from
/// CLN); which of the two, or a later out-of-memory, depends on a few hundred kB of layout that
/// moves with every build. A floor well above the need turns the whole band into one clear
/// refusal. No command does useful work in less: the compiler nhc starts needs hundreds of MB.
/// 64 MB was that floor until `nhc ensemble --threads 2` of a cached particle needed about
/// 65.5 MB (its threads' stacks, HDF5): at 64 MB it ran out inside HDF5, which then crashed.
constexpr rlim_t kLeastAddressSpace = rlim_t{96} << 20;

/// True (and says why) when an address-space limit is below kLeastAddressSpace.
bool address_space_too_small() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY || limit.rlim_cur >= kLeastAddressSpace)
    return false;
  std::fprintf(stderr,
               "nhc: error: the address-space limit (ulimit -v) is %llu kB, below the %llu kB nhc needs to load "
               "its libraries: raise the limit\n",
               static_cast<unsigned long long>(limit.rlim_cur >> 10),
               static_cast<unsigned long long>(kLeastAddressSpace >> 10));
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (address_space_too_small()) return nhc::cli::kExitEnvironment;
  const int current = personality(0xffffffff);  // query only
  if (current != -1 && (current & ADDR_NO_RANDOMIZE) == 0)
    personality(static_cast<unsigned long>(current) | ADDR_NO_RANDOMIZE);  // refused: goes on randomized
  heap_in_huge_pages();
  const std::string directory = nhc::cli::own_directory();
  // nhc-main, or the program of a command of command_programs.hpp (nhc ensemble: nhc-ensemble).
  const nhc::cli::CommandProgram* entry = argc > 1 ? nhc::cli::command_program(argv[1]) : nullptr;
  const std::string name = entry ? entry->program : "nhc-main";
  // Beside this file in a build tree; under libexec/nhc/ once installed (cmake/nhcInstall.cmake).
  const std::string candidates[] = {directory + "/" + name, directory + "/../" NHC_LIBEXEC_DIR "/nhc/" + name};
  int error = ENOENT;
  for (const std::string& program : candidates) {
    if (directory.empty()) break;
    execv(program.c_str(), argv);
    error = errno;
  }
  std::fprintf(stderr, "nhc: error: cannot start the nhc program (%s/%s or %s/../%s/nhc/%s): %s\n", directory.c_str(),
               name.c_str(), directory.c_str(), NHC_LIBEXEC_DIR, name.c_str(), std::strerror(error));
  return nhc::cli::kExitEnvironment;
}
