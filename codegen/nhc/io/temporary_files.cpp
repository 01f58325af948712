#include "nhc/io/temporary_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
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
PathSlot directory_slots[kSlots];

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

/// Claims a free slot of `slots` for `path`; -1 when none is free.
int register_path(PathSlot* slots, const std::string& path) {
  if (path.size() >= kPathCapacity) throw std::runtime_error("temporary file name too long: " + path);
  for (int k = 0; k < kSlots; ++k) {
    int expected = 0;
    if (slots[k].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(slots[k].path, path.c_str(), path.size() + 1);
      slots[k].state.store(2);
      return k;
    }
  }
  return -1;
}

/// Async-signal-safe removal of a flat directory: its entries by getdents64 and unlinkat, then
/// the directory (opendir/readdir may allocate and are not safe in a handler).
void remove_flat_directory(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buffer[4096];
    // Entries are removed while the directory is read: read again from the start until only
    // "." and ".." are left (bounded, in case an entry cannot be removed).
    for (int pass = 0; pass < 64; ++pass) {
      ::lseek(fd, 0, SEEK_SET);
      bool removed = false;
      long n;
      while ((n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0) {
        for (long offset = 0; offset < n;) {
          // struct linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name.
          unsigned short record_length;
          std::memcpy(&record_length, buffer + offset + 16, sizeof record_length);
          const char* name = buffer + offset + 19;
          const bool dots = name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0));
          if (!dots && ::unlinkat(fd, name, 0) == 0) removed = true;
          offset += record_length;
        }
      }
      if (!removed) break;
    }
    ::close(fd);
  }
  ::rmdir(path);
}

}  // namespace

TemporaryFile::TemporaryFile(std::string path) : path_(std::move(path)) {
  slot_ = register_path(path_slots, path_);
  if (slot_ < 0) throw std::runtime_error("too many temporary files at once");
}

TemporaryFile::~TemporaryFile() {
  // Gone after a successful rename; still there when an exception left the work unfinished.
  ::unlink(path_.c_str());
  if (slot_ >= 0) path_slots[slot_].state.store(0);
}

void TemporaryFile::remove() const noexcept { ::unlink(path_.c_str()); }

TemporaryDirectory::TemporaryDirectory(std::string path) : path_(std::move(path)) {
  slot_ = register_path(directory_slots, path_);
  if (slot_ < 0) throw std::runtime_error("too many temporary directories at once");
}

TemporaryDirectory::~TemporaryDirectory() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);  // nothing left after a successful rename
  if (slot_ >= 0) directory_slots[slot_].state.store(0);
}

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
  for (auto& slot : directory_slots)
    if (slot.state.load() == 2) remove_flat_directory(slot.path);
}

}  // namespace nhc
