#include "nhc/io/atomic_directory.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "nhc/errors.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/io/temporary_files.hpp"

namespace nhc {

namespace fs = std::filesystem;

namespace {

/// Creates the missing ancestors of `path` (outermost first); returns them innermost first.
std::vector<std::string> create_parents(const fs::path& path) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = path.parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  std::vector<std::string> created;
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
      const std::string reason = std::strerror(errno);
      for (const std::string& c : created) ::rmdir(c.c_str());
      throw EnvironmentError("cannot create the directory " + it->string() + ": " + reason);
    }
    created.insert(created.begin(), it->string());
  }
  return created;
}

}  // namespace

AtomicDirectory::AtomicDirectory(std::string target, std::vector<std::string> inputs)
    : target_(std::move(target)), inputs_(std::move(inputs)) {
  while (target_.size() > 1 && target_.back() == '/') target_.pop_back();
  check_output_directory(target_, inputs_);
  created_parents_ = create_parents(fs::path(target_));
  // Registered before it exists: an interrupt at any moment removes it (temporary_files.hpp).
  temporary_ = std::make_unique<TemporaryDirectory>(unique_temporary_name(target_));
  if (::mkdir(temporary_->path().c_str(), 0777) != 0) {
    const std::string reason = std::strerror(errno);
    temporary_.reset();
    for (const std::string& c : created_parents_) ::rmdir(c.c_str());
    throw EnvironmentError("cannot create the directory " + target_ + ": " + reason);
  }
}

AtomicDirectory::~AtomicDirectory() {
  temporary_.reset();  // removes what is left of the temporary directory
  if (!committed_)
    for (const std::string& c : created_parents_) ::rmdir(c.c_str());  // only when empty
}

const std::string& AtomicDirectory::path() const noexcept { return temporary_->path(); }

std::string AtomicDirectory::file(const std::string& name) const { return (fs::path(path()) / name).string(); }

std::string AtomicDirectory::final_file(const std::string& name) const { return (fs::path(target_) / name).string(); }

void AtomicDirectory::commit() {
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    if (std::rename(path().c_str(), target_.c_str()) == 0) {
      committed_ = true;
      return;
    }
    // Another run made the directory in the meantime: move the files into it as below.
    if (errno != ENOTEMPTY && errno != EEXIST)
      throw EnvironmentError("cannot move " + path() + " to " + target_ + ": " + std::strerror(errno));
  }
  check_output_directory(target_, inputs_);
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(path())) {
    const std::string name = entry.path().filename().string();
    check_output_file(final_file(name), inputs_);
    names.push_back(name);
  }
  for (const std::string& name : names)
    if (std::rename(file(name).c_str(), final_file(name).c_str()) != 0)
      throw EnvironmentError("cannot move " + file(name) + " to " + final_file(name) + ": " + std::strerror(errno));
  committed_ = true;
}

}  // namespace nhc
