#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/parent_directories.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/io/temporary_files.hpp"

namespace nhc {

namespace fs = std::filesystem;

AtomicDirectory::AtomicDirectory(std::string target, std::vector<std::string> inputs)
    : target_(std::move(target)), inputs_(std::move(inputs)) {
  while (target_.size() > 1 && target_.back() == '/') target_.pop_back();
  check_output_directory(target_, inputs_);
  created_parents_ = create_missing_parents(target_);
  // Registered before it exists: an interrupt at any moment removes it (temporary_files.hpp).
  temporary_ = std::make_unique<TemporaryDirectory>(unique_temporary_name(target_));
  if (::mkdir(temporary_->path().c_str(), 0777) != 0) {
    const std::string reason = std::strerror(errno);
    temporary_.reset();
    remove_created_parents(created_parents_);
    throw EnvironmentError("cannot create the directory " + target_ + ": " + reason);
  }
}

AtomicDirectory::~AtomicDirectory() {
  temporary_.reset();  // removes what is left of the temporary directory
  if (!committed_) remove_created_parents(created_parents_);
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
  for (const std::string& name : names) {
    const OutputTarget target = output_target(final_file(name));
    if (target.kind == OutputTarget::Kind::stream || target.path != final_file(name)) {
      // A link's target (the link stays) or a device: written by the one policy (output_path.hpp).
      std::ifstream in(file(name), std::ios::binary);
      write_file_atomically(final_file(name), [&](std::ostream& out) { out << in.rdbuf(); });
    } else if (std::rename(file(name).c_str(), final_file(name).c_str()) != 0) {
      throw EnvironmentError("cannot move " + file(name) + " to " + final_file(name) + ": " + std::strerror(errno));
    }
  }
  committed_ = true;
}

}  // namespace nhc
