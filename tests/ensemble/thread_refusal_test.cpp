// The scheduler when the machine refuses threads: with room for no worker's
// stack, the refusal reaches the caller as std::system_error (the command line's exit 4, "the
// machine refused a resource") instead of aborting with threads joinable; with room for one of
// two, that one does every run. The room is made exact by an address-space limit set just above
// what the process maps now, in this test process only (each test case runs in its own). Not
// under AddressSanitizer, whose shadow memory and fake stacks change what a thread maps.
#include <catch2/catch.hpp>
#include <pthread.h>
#include <sys/resource.h>

#include <cstdint>
#include <fstream>
#include <numeric>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "nhc/ensemble/scheduler.hpp"
#include "nhc/ensemble/session.hpp"

namespace {

namespace ne = nhc::ensemble;

/// Bytes of address space the process maps now (/proc/self/status VmSize).
rlim_t mapped_now() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) return static_cast<rlim_t>(std::stoull(line.substr(7))) << 10;
  FAIL("no VmSize in /proc/self/status");
  return 0;
}

/// The stack glibc gives a new thread by default.
std::size_t default_thread_stack() {
  pthread_attr_t attributes;
  REQUIRE(pthread_getattr_default_np(&attributes) == 0);
  std::size_t size = 0;
  pthread_attr_getstacksize(&attributes, &size);
  pthread_attr_destroy(&attributes);
  return size;
}

/// An address-space limit `room` bytes above the current mapping, lifted again at scope exit.
class AddressSpaceRoom {
 public:
  explicit AddressSpaceRoom(rlim_t room) {
    REQUIRE(getrlimit(RLIMIT_AS, &saved_) == 0);
    rlimit limited = saved_;
    limited.rlim_cur = mapped_now() + room;
    REQUIRE(setrlimit(RLIMIT_AS, &limited) == 0);
  }
  ~AddressSpaceRoom() { setrlimit(RLIMIT_AS, &saved_); }

 private:
  rlimit saved_{};
};

/// Schedules `runs` trivial runs on 2 threads; returns the indices delivered.
std::set<std::int64_t> schedule_on_two_threads(const ne::Session& session, std::int64_t runs) {
  std::vector<std::int64_t> todo(static_cast<std::size_t>(runs));
  std::iota(todo.begin(), todo.end(), 0);
  std::set<std::int64_t> delivered;
  const double value = 0;
  ne::ScheduleOptions options;
  options.threads = 2;
  options.values = [&](std::int64_t) { return &value; };
  options.on_records = [&](std::vector<ne::RunRecord>&& records) {
    for (const ne::RunRecord& r : records) delivered.insert(r.index);
  };
  options.on_idle = [] {};
  const ne::RunFunction run = [](std::int64_t index, const double*) {
    ne::RunRecord r;
    r.index = index;
    r.outcome = ne::Outcome::ok;
    return r;
  };
  ne::schedule(session, todo, run, options);
  return delivered;
}

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kUnderAddressSanitizer = true;
#else
constexpr bool kUnderAddressSanitizer = false;
#endif

}  // namespace

TEST_CASE("no room for a worker thread: the refusal reaches the caller, nothing aborts", "[ensemble]") {
  if (kUnderAddressSanitizer) return;
  const ne::Session session;
  const std::size_t stack = default_thread_stack();
  REQUIRE(stack >= (std::size_t{1} << 20));  // the room below must be too small for one stack
  std::set<std::int64_t> delivered;
  {
    const AddressSpaceRoom room(256 << 10);
    CHECK_THROWS_AS(delivered = schedule_on_two_threads(session, 50), std::system_error);
  }
  CHECK(delivered.empty());
}

TEST_CASE("room for one worker thread of two: it does every run", "[ensemble]") {
  if (kUnderAddressSanitizer) return;
  const ne::Session session;
  const std::size_t stack = default_thread_stack();
  std::set<std::int64_t> delivered;
  {
    // One stack and its guard page fit, a second does not.
    const AddressSpaceRoom room(static_cast<rlim_t>(stack + stack / 2));
    delivered = schedule_on_two_threads(session, 50);
  }
  CHECK(delivered.size() == 50);
}
