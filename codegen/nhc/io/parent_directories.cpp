#include "nhc/io/parent_directories.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "nhc/errors.hpp"

namespace nhc {

namespace fs = std::filesystem;

std::vector<std::string> create_missing_parents(const std::string& path) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = fs::path(path).parent_path(); !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  std::vector<std::string> created;
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0777) != 0 && errno != EEXIST) {
      const std::string reason = std::strerror(errno);
      remove_created_parents(created);
      throw EnvironmentError("cannot create the directory " + it->string() + ": " + reason);
    }
    created.insert(created.begin(), it->string());
  }
  return created;
}

void check_can_create(const std::string& path) {
  std::error_code ec;
  fs::path ancestor = fs::absolute(fs::path(path), ec).parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, ec) && ancestor != ancestor.parent_path())
    ancestor = ancestor.parent_path();
  errno = 0;
  if (!fs::is_directory(ancestor, ec)) errno = ENOTDIR;
  else if (::access(ancestor.c_str(), W_OK | X_OK) != 0 && errno == 0) errno = EACCES;
  if (errno != 0) throw EnvironmentError("cannot write " + path + ": " + std::strerror(errno));
}

void remove_created_parents(const std::vector<std::string>& created) {
  for (const std::string& c : created) ::rmdir(c.c_str());  // fails, harmlessly, unless empty
}

}  // namespace nhc
