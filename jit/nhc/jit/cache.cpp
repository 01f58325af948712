// The private, verified compile cache (cache.hpp).
#include "nhc/io/temporary_files.hpp"
#include "nhc/jit/cache.hpp"
#include "nhc/jit/cache_size.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/tools/sha256.hpp"

namespace nhc::jit {

namespace fs = std::filesystem;
using tools::sha256_file_hex;

namespace {

std::string octal_mode(mode_t mode) {
  std::ostringstream os;
  os << std::oct << (mode & 07777);
  return "0" + os.str();
}

/// Why the directory cannot hold the cache; empty when it is private to the user.
std::string directory_problem(const fs::path& dir, bool follow_links) {
  struct stat st {};
  if ((follow_links ? ::stat(dir.c_str(), &st) : ::lstat(dir.c_str(), &st)) != 0) return std::strerror(errno);
  if (S_ISLNK(st.st_mode)) return "it is a symbolic link";
  if (!S_ISDIR(st.st_mode)) return "it is not a directory";
  if (st.st_uid != ::geteuid())
    return "it is owned by user id " + std::to_string(st.st_uid) + ", not by you (user id " +
           std::to_string(::geteuid()) + ")";
  if (st.st_mode & (S_IWGRP | S_IWOTH))
    return std::string("it is writable by ") + ((st.st_mode & S_IWOTH) ? "others" : "its group") + " (mode " +
           octal_mode(st.st_mode) + ")";
  return {};
}

/// Creates `dir` with mode 0700 (and its missing parents with the usual mode); an existing one
/// is left for the checks.
void create_private(const fs::path& dir) {
  std::error_code ec;
  if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
  if (ec) throw EnvironmentError("cannot create the compile cache " + dir.string() + ": " + ec.message());
  if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
    throw EnvironmentError("cannot create the compile cache " + dir.string() + ": " + std::strerror(errno));
}

fs::path fresh_private_directory(const fs::path& beside) {
  std::string name = beside.string() + "-XXXXXX";
  if (!::mkdtemp(name.data()))  // mode 0700, a name no one else could have taken
    throw EnvironmentError("cannot create a private compile cache beside " + beside.string() + ": " +
                           std::strerror(errno));
  return name;
}

}  // namespace

CacheLocation default_cache_location() {
  if (const char* dir = std::getenv("NHC_CACHE_DIR"); dir && *dir) return {dir, false};
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return {fs::path(xdg) / "nhc", false};
  if (const char* home = std::getenv("HOME"); home && *home) return {fs::path(home) / ".cache" / "nhc", false};
  std::error_code ec;
  fs::path temporary = fs::temp_directory_path(ec);
  if (ec) temporary = "/tmp";
  return {temporary / ("nhc-cache-" + std::to_string(::geteuid())), true};
}

fs::path private_cache_directory(const CacheLocation& location, const Warning& warn) {
  const fs::path& dir = location.path;
  if (location.temporary_fallback) {
    // A shared, sticky directory: whoever creates the name first owns it. Never follow a link.
    if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
      throw EnvironmentError("cannot create the compile cache " + dir.string() + ": " + std::strerror(errno));
    const std::string problem = directory_problem(dir, false);
    if (problem.empty()) return dir;
    const fs::path fresh = fresh_private_directory(dir);
    warn("the compile cache " + dir.string() + " is not private (" + problem + "); not used: this run uses " +
         fresh.string() + " (set NHC_CACHE_DIR or HOME to keep a cache)");
    return fresh;
  }
  create_private(dir);
  const std::string problem = directory_problem(dir, true);
  if (!problem.empty())
    throw EnvironmentError("the compile cache " + dir.string() + " is unusable: " + problem +
                           "; it must be a directory owned by you and writable only by you (chmod 700 it, or "
                           "set NHC_CACHE_DIR to another directory)");
  sweep_stale_temporaries(dir.string());  // what a killed nhc left behind
  return dir;
}

fs::path digest_path(const fs::path& library) { return fs::path(library.string() + ".sha256"); }

std::string digest_text(const std::string& sha256, const std::string& file_name) {
  return sha256 + "  " + file_name + "\n";
}

std::string entry_problem(const fs::path& library) {
  struct stat st {};
  if (::lstat(library.c_str(), &st) != 0) return std::strerror(errno);
  if (!S_ISREG(st.st_mode)) return "not a regular file";
  if (st.st_uid != ::geteuid()) return "owned by user id " + std::to_string(st.st_uid) + ", not by you";
  if (st.st_mode & (S_IWGRP | S_IWOTH)) return "writable by others (mode " + octal_mode(st.st_mode) + ")";
  const fs::path sidecar = digest_path(library);
  std::ifstream in(sidecar);
  std::string recorded;
  if (!(in >> recorded) || recorded.size() != 64) return "no digest (" + sidecar.filename().string() + ")";
  const std::optional<std::string> actual = sha256_file_hex(library);
  if (!actual) return "unreadable";
  if (*actual != recorded) return "its bytes do not match its SHA-256 digest (damaged or replaced)";
  return {};
}

void discard_entry(const fs::path& library) noexcept {
  ::unlink(library.c_str());
  ::unlink(digest_path(library).c_str());
}

std::uintmax_t cache_size_limit() {
  constexpr std::uintmax_t kDefault = std::uintmax_t{2} << 30;
  const char* setting = std::getenv("NHC_CACHE_MAX_SIZE");
  if (!setting || !*setting) return kDefault;
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(setting, &end, 10);
  if (errno != 0 || end == setting) return kDefault;
  const std::string suffix = end;
  const int shift = suffix.empty() ? 0 : suffix == "K" ? 10 : suffix == "M" ? 20 : suffix == "G" ? 30 : -1;
  if (shift < 0 || value > (~std::uintmax_t{0} >> shift)) return kDefault;
  return static_cast<std::uintmax_t>(value) << shift;
}

void mark_used(const fs::path& entry) noexcept { ::utimensat(AT_FDCWD, entry.c_str(), nullptr, AT_SYMLINK_NOFOLLOW); }

void evict_over_limit(const fs::path& directory, const fs::path& keep) noexcept {
  const std::uintmax_t limit = cache_size_limit();
  if (limit == 0) return;
  struct Entry {
    fs::path path;
    std::uintmax_t bytes;
    fs::file_time_type used;
    bool library;
  };
  std::vector<Entry> entries;
  std::uintmax_t total = 0;
  std::error_code ec;
  auto collect = [&](const fs::path& dir, const std::string& extension, bool library) {
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      const fs::path& path = it->path();
      if (path.extension() != extension || !it->is_regular_file(ec)) continue;
      std::uintmax_t bytes = it->file_size(ec);
      if (library) bytes += fs::file_size(digest_path(path), ec), ec.clear();
      const fs::file_time_type used = it->last_write_time(ec);
      if (ec) {
        ec.clear();
        continue;
      }
      total += bytes;
      entries.push_back({path, bytes, used, library});
    }
    ec.clear();
  };
  collect(directory, ".so", true);
  collect(directory / "scenes", ".entry", false);
  if (total <= limit) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  const std::uintmax_t target = limit / 10 * 9;
  for (const Entry& e : entries) {
    if (total <= target) break;
    if (e.path == keep) continue;
    if (e.library) discard_entry(e.path);
    else ::unlink(e.path.c_str());
    total -= e.bytes;
  }
}

}  // namespace nhc::jit
