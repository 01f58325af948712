#pragma once
/// \file temporary_files.hpp
/// \brief Temporary files and child processes that must not outlive an interrupted nhc run.
///
/// Output files are written to a temporary name and renamed (atomic_file.hpp). The library only
/// keeps the registry; installing signal handlers is the application's business (the nhc
/// command's is cli/interrupt.cpp): a handler calls cleanup_after_signal(), which stops the
/// registered child processes (a compiler the library started) and removes the registered
/// temporary files. Registration is a fixed table of slots written with atomics, so the cleanup
/// is async-signal-safe (only kill, waitpid, nanosleep and unlink).

#include <sys/types.h>

#include <string>

namespace nhc {

/// Registers `path` for removal by cleanup_after_signal() for the lifetime of this object, and
/// removes the file (if it still exists: not renamed) when the object goes out of scope, also by
/// an exception. Register before creating the file, so that no moment exists at which it could
/// be left behind.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::string path);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  const std::string& path() const noexcept { return path_; }
  /// Removes the file now if it still exists (after a failure); the registration stays.
  void remove() const noexcept;

 private:
  std::string path_;
  int slot_ = -1;
};

/// A temporary directory of flat content (files, no subdirectories), registered like a
/// TemporaryFile: cleanup_after_signal() and the destructor remove its files and the directory
/// itself unless it was renamed away (AtomicDirectory). Register before creating it.
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(std::string path);
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::string& path() const noexcept { return path_; }
  /// Removes the directory and its files now, if it still exists.
  void remove() const noexcept;

 private:
  std::string path_;
  int slot_ = -1;
};

/// Registers a running child process group (leader `pid`) to be terminated by
/// cleanup_after_signal() for the lifetime of this object.
class ChildProcessGroup {
 public:
  explicit ChildProcessGroup(pid_t pid);
  ~ChildProcessGroup();
  ChildProcessGroup(const ChildProcessGroup&) = delete;
  ChildProcessGroup& operator=(const ChildProcessGroup&) = delete;

 private:
  int slot_ = -1;
};

/// A name beside `path` for its temporary file: `<path>.tmp<pid>_<counter><random>`, unique
/// among concurrent processes and among the calls of one process.
std::string unique_temporary_name(const std::string& path);

/// Removes the temporaries of processes that are gone (kill -9 leaves them; nothing else would)
/// directly inside `directory`: names made by unique_temporary_name() whose pid no longer runs on
/// this machine and which are older than `min_age_seconds` (a cache shared over a network may
/// hold live temporaries of another machine's pids). Returns how many it removed; never throws.
int sweep_stale_temporaries(const std::string& directory, double min_age_seconds = 600);

/// Async-signal-safe: sends SIGTERM to the registered child process groups and waits for them
/// (SIGKILL after two seconds), then unlinks every registered temporary file and removes every
/// registered temporary directory with its files.
void cleanup_after_signal() noexcept;

}  // namespace nhc
