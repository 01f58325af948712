#include "nhc/io/temporary_files.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <random>
#include <stdexcept>

namespace nhc {

namespace {

// Fixed storage, no allocation in the signal handler. A slot is free (0), being filled (1) or
// registered (2); the handler only reads registered slots, whose text is complete.
constexpr int kSlots = 64;
constexpr std::size_t kPathCapacity = 4096;

struct PathSlot {
  std::atomic<int> state{0};
  char path[kPathCapacity];
};
PathSlot path_slots[kSlots];

struct ChildSlot {
  std::atomic<pid_t> pid{0};
};
ChildSlot child_slots[kSlots];

static_assert(std::atomic<int>::is_always_lock_free, "signal-safe registry needs lock-free int");
static_assert(std::atomic<pid_t>::is_always_lock_free, "signal-safe registry needs lock-free pid_t");

void pause_briefly() noexcept {
  timespec delay{0, 20 * 1000 * 1000};  // 20 ms
  while (nanosleep(&delay, &delay) != 0 && errno == EINTR) {
  }
}

}  // namespace

TemporaryFile::TemporaryFile(std::string path) : path_(std::move(path)) {
  if (path_.size() >= kPathCapacity)
    throw std::runtime_error("temporary file name too long: " + path_);
  for (int k = 0; k < kSlots; ++k) {
    int expected = 0;
    if (path_slots[k].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(path_slots[k].path, path_.c_str(), path_.size() + 1);
      path_slots[k].state.store(2);
      slot_ = k;
      return;
    }
  }
  throw std::runtime_error("too many temporary files at once");
}

TemporaryFile::~TemporaryFile() {
  // Gone after a successful rename; still there when an exception left the work unfinished.
  ::unlink(path_.c_str());
  if (slot_ >= 0) path_slots[slot_].state.store(0);
}

void TemporaryFile::remove() const noexcept { ::unlink(path_.c_str()); }

ChildProcessGroup::ChildProcessGroup(pid_t pid) {
  for (int k = 0; k < kSlots; ++k) {
    pid_t expected = 0;
    if (child_slots[k].pid.compare_exchange_strong(expected, pid)) {
      slot_ = k;
      return;
    }
  }
  // No free slot: the child simply is not stopped by an interrupt; nothing else depends on it.
}

ChildProcessGroup::~ChildProcessGroup() {
  if (slot_ >= 0) child_slots[slot_].pid.store(0);
}

std::string unique_temporary_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  static const unsigned salt = std::random_device{}() % 1000000u;
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" +
         std::to_string(salt);
}

void cleanup_after_signal() noexcept {
  // Stop the children first: a compiler still running could otherwise recreate its output.
  for (auto& slot : child_slots) {
    const pid_t pid = slot.pid.load();
    if (pid > 0) ::kill(-pid, SIGTERM);
  }
  for (auto& slot : child_slots) {
    const pid_t pid = slot.pid.load();
    if (pid <= 0) continue;
    bool finished = false;
    for (int tries = 0; tries < 100 && !finished; ++tries) {  // two seconds
      const pid_t r = ::waitpid(pid, nullptr, WNOHANG);
      finished = r == pid || (r < 0 && errno != EINTR);
      if (!finished) pause_briefly();
    }
    if (!finished) {
      ::kill(-pid, SIGKILL);
      while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
      }
    }
  }
  for (auto& slot : path_slots)
    if (slot.state.load() == 2) ::unlink(slot.path);
}

}  // namespace nhc
