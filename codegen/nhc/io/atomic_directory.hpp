#pragma once
/// \file atomic_directory.hpp
/// \brief Writing an output directory so that it appears whole or not at all: its files are
/// written into a temporary sibling directory, which is renamed into place when complete.
///
///   nhc::AtomicDirectory out("results", "-o", "compare.md");
///   write_file(out.path() / "compare.md");       // … every file of the output
///   out.commit();                                 // results/ now holds exactly these files
///
/// Until commit() nothing is visible at the target; when the object is destroyed uncommitted
/// (an exception), or the process is interrupted (temporary_files.hpp), the temporary directory
/// and its files are removed and an existing target is untouched. The temporary directory is
/// flat: files only, no subdirectories (so that a signal handler can remove it).

#include <filesystem>
#include <string>

#include "nhc/io/temporary_files.hpp"

namespace nhc {

class AtomicDirectory {
 public:
  /// Prepares `target`. It may be missing, an empty directory, or a directory holding `marker`
  /// (an earlier output of the same command, which commit() replaces as a whole); anything else
  /// is refused with an InputError naming `flag`, so that `-o` never deletes unrelated files.
  /// Also InputError when the temporary sibling cannot be created (no such parent, no rights).
  AtomicDirectory(const std::filesystem::path& target, const std::string& flag, const std::string& marker);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  /// The temporary directory to write the files into.
  const std::filesystem::path& path() const noexcept { return staging_; }
  const std::filesystem::path& target() const noexcept { return target_; }

  /// Puts the files in place: renames the temporary directory to the target, exchanging it
  /// atomically with an existing one (renameat2 RENAME_EXCHANGE; where the file system cannot,
  /// two renames), then removes the old content. InputError (flag) when it cannot.
  void commit();

 private:
  std::filesystem::path target_;
  std::string flag_;
  std::filesystem::path staging_;
  TemporaryDirectory registration_;
  bool committed_ = false;
};

}  // namespace nhc
