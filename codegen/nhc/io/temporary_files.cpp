#include "nhc/io/temporary_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
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
  bool directory = false;  // written before state becomes 2
  char path[kPathCapacity];
};
PathSlot path_slots[kSlots];

int register_path(const std::string& path, bool directory) {
  if (path.size() >= kPathCapacity) throw std::runtime_error("temporary file name too long: " + path);
  for (int k = 0; k < kSlots; ++k) {
    int expected = 0;
    if (path_slots[k].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(path_slots[k].path, path.c_str(), path.size() + 1);
      path_slots[k].directory = directory;
      path_slots[k].state.store(2);
      return k;
    }
  }
  throw std::runtime_error("too many temporary files at once");
}

/// Async-signal-safe removal of a flat directory: raw getdents64, unlinkat, rmdir (no malloc).
void remove_flat_directory(const char* path) noexcept {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buffer[8192];
    for (;;) {
      const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (n <= 0) break;
      for (long offset = 0; offset < n;) {
        struct LinuxDirent64 {
          ino64_t d_ino;
          off64_t d_off;
          unsigned short d_reclen;
          unsigned char d_type;
          char d_name[1];
        };
        const auto* entry = reinterpret_cast<const LinuxDirent64*>(buffer + offset);
        const char* name = entry->d_name;
        const bool dot = name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0));
        if (!dot) ::unlinkat(fd, name, 0);
        offset += entry->d_reclen;
      }
    }
    ::close(fd);
  }
  ::rmdir(path);
}

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

TemporaryFile::TemporaryFile(std::string path) : path_(std::move(path)), slot_(register_path(path_, false)) {}

TemporaryFile::~TemporaryFile() {
  // Gone after a successful rename; still there when an exception left the work unfinished.
  ::unlink(path_.c_str());
  if (slot_ >= 0) path_slots[slot_].state.store(0);
}

void TemporaryFile::remove() const noexcept { ::unlink(path_.c_str()); }

TemporaryDirectory::TemporaryDirectory(std::string path) : path_(std::move(path)), slot_(register_path(path_, true)) {}

TemporaryDirectory::~TemporaryDirectory() {
  remove();
  if (slot_ >= 0) path_slots[slot_].state.store(0);
}

void TemporaryDirectory::remove() const noexcept { remove_flat_directory(path_.c_str()); }

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
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + std::to_string(salt);
}

int sweep_stale_temporaries(const std::string& directory, double min_age_seconds) {
  namespace fs = std::filesystem;
  int removed = 0;
  std::error_code ec;
  const auto now = fs::file_time_type::clock::now();
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    // <name>.tmp<pid>_<counter>_<salt>
    const std::size_t at = name.rfind(".tmp");
    if (at == std::string::npos) continue;
    char* rest = nullptr;
    const long pid = std::strtol(name.c_str() + at + 4, &rest, 10);
    if (pid <= 0 || rest == name.c_str() + at + 4 || *rest != '_') continue;
    if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code time_error;
    const auto written = fs::last_write_time(it->path(), time_error);
    if (time_error || std::chrono::duration<double>(now - written).count() < min_age_seconds) continue;
    std::error_code remove_error;
    if (fs::remove_all(it->path(), remove_error) > 0 && !remove_error) ++removed;
  }
  return removed;
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
    if (slot.state.load() == 2 && !slot.directory) ::unlink(slot.path);
  for (auto& slot : path_slots)
    if (slot.state.load() == 2 && slot.directory) remove_flat_directory(slot.path);
}

}  // namespace nhc
