#pragma once
/// \file temporary_files.hpp
/// \brief Temporary files and child processes that must not outlive an interrupted nhc run.
///
/// Output files are written to a temporary name and renamed (atomic_file.hpp). When SIGINT or
/// SIGTERM arrives in between, the command's signal handler calls cleanup_after_signal(), which
/// stops the registered child processes (the C++ compiler of `nhc simulate`) and removes the
/// registered temporary files. Registration is a fixed table of slots written with atomics, so
/// the cleanup is async-signal-safe (only kill, waitpid, nanosleep, open, getdents64, unlink,
/// unlinkat and rmdir).

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

/// Registers a directory of files (no subdirectories) for removal, with its files, by
/// cleanup_after_signal() for the lifetime of this object; the destructor removes it too when it
/// still exists (not renamed). Used by AtomicDirectory (atomic_directory.hpp).
class TemporaryDirectory {
 public:
  explicit TemporaryDirectory(std::string path);
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::string& path() const noexcept { return path_; }

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

/// Async-signal-safe: sends SIGTERM to the registered child process groups and waits for them
/// (SIGKILL after two seconds), then unlinks every registered temporary file.
void cleanup_after_signal() noexcept;

}  // namespace nhc
