#pragma once
/// \file atomic_directory.hpp
/// \brief Directory outputs (nhc report -o DIR) built completely or not at all: the files are
/// written into a temporary sibling directory, which is moved into place at the end. On failure
/// or interrupt nothing new is left and an existing DIR is untouched.

#include <memory>
#include <string>
#include <vector>

namespace nhc {

class TemporaryDirectory;

class AtomicDirectory {
 public:
  /// Creates `<target>.tmp<pid>_…` beside `target` (and target's missing parents, removed again
  /// when nothing is committed). Throws InputError (exit 2) when `target` is one of `inputs` or
  /// an existing non-directory, EnvironmentError (exit 4) when the directory cannot be created.
  explicit AtomicDirectory(std::string target, std::vector<std::string> inputs = {});
  /// Not committed: removes the temporary directory, its files and the parents it created.
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  /// Where the files are written until commit(): the temporary directory.
  const std::string& path() const noexcept;
  /// `path()/name`, and where that file ends up after commit().
  std::string file(const std::string& name) const;
  std::string final_file(const std::string& name) const;
  const std::string& target() const noexcept { return target_; }

  /// Moves the content into place: a new target is the temporary directory renamed (one atomic
  /// step); into an existing target each file is renamed over its namesake, other files there
  /// are left alone. Refuses (InputError) a file that would replace one of the inputs, before
  /// moving anything. Throws EnvironmentError naming the path when a rename fails.
  void commit();

 private:
  std::string target_;
  std::vector<std::string> inputs_;
  std::vector<std::string> created_parents_;  // innermost first
  std::unique_ptr<TemporaryDirectory> temporary_;
  bool committed_ = false;
};

}  // namespace nhc
