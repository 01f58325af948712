#include "nhc/io/atomic_directory.hpp"

#include <fcntl.h>
#include <stdio.h>  // renameat2 (glibc >= 2.28, _GNU_SOURCE)

#include <cerrno>
#include <cstring>
#include <system_error>

#include "nhc/errors.hpp"

namespace nhc {

namespace fs = std::filesystem;

namespace {

/// Whether `dir` may be replaced: empty, or holding `marker` (an earlier output).
bool replaceable(const fs::path& dir, const std::string& marker) {
  std::error_code ec;
  if (fs::is_empty(dir, ec) && !ec) return true;
  return !marker.empty() && fs::is_regular_file(dir / marker, ec);
}

/// The directory itself, without a trailing slash ("out/" names "out").
fs::path without_trailing_separator(const fs::path& p) {
  return p.has_filename() ? p : p.parent_path();
}

}  // namespace

AtomicDirectory::AtomicDirectory(const fs::path& target, const std::string& flag, const std::string& marker)
    : target_(without_trailing_separator(target)),
      flag_(flag),
      staging_(unique_temporary_name(target_.string())),
      registration_(staging_.string()) {
  auto refuse = [&](const std::string& why) { throw InputError({flag_, 0, 0}, target_.string() + ": " + why); };
  if (target_.empty()) refuse("an empty directory name");
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target_, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) refuse("exists and is not a directory");
    if (!replaceable(target_, marker))
      refuse("exists and is not an earlier output (no " + marker +
             "); refusing to replace its files: name a new or empty directory");
  }
  if (!fs::create_directory(staging_, ec))
    refuse("cannot create a directory beside it: " + (ec ? ec.message() : std::string("exists")));
}

AtomicDirectory::~AtomicDirectory() = default;  // the registration removes an uncommitted staging directory

void AtomicDirectory::commit() {
  if (committed_) return;
  auto fail = [&](const std::string& why) { throw InputError({flag_, 0, 0}, target_.string() + ": " + why); };
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(target_, ec))) {
    if (std::rename(staging_.c_str(), target_.c_str()) != 0) fail(std::string("cannot create: ") + std::strerror(errno));
    committed_ = true;
    return;
  }
  // Exchange: the target shows the old files or the new ones, never a mixture or nothing; the
  // old ones are then under the staging name, which the registration removes.
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    committed_ = true;
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    fail(std::string("cannot replace: ") + std::strerror(errno));
  // A file system without RENAME_EXCHANGE: move the old directory aside, then the new one in.
  const fs::path old = unique_temporary_name(target_.string());
  if (std::rename(target_.c_str(), old.c_str()) != 0) fail(std::string("cannot replace: ") + std::strerror(errno));
  if (std::rename(staging_.c_str(), target_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::rename(old.c_str(), target_.c_str());
    fail("cannot replace: " + why);
  }
  committed_ = true;
  fs::remove_all(old, ec);
}

}  // namespace nhc
