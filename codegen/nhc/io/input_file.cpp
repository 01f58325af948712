#include "nhc/io/input_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string megabytes(std::uintmax_t bytes) {
  return std::to_string((bytes + (std::uintmax_t{1} << 20) - 1) >> 20) + " MB";
}

}  // namespace

void check_input_file(const std::string& path, const std::string& what, std::uintmax_t limit) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0)
    throw InputError({path, 0, 0}, "cannot read " + what + ": " + std::strerror(errno));
  if (!S_ISREG(s.st_mode)) throw InputError({path, 0, 0}, "is " + kind_of(s.st_mode) + ", not " + what);
  if (static_cast<std::uintmax_t>(s.st_size) > limit)
    throw InputError({path, 0, 0}, "is " + megabytes(static_cast<std::uintmax_t>(s.st_size)) + ", more than the " +
                                       megabytes(limit) + " nhc reads as " + what + " (docs/safety.md)");
}

std::string read_input_file(const std::string& path, const std::string& what) {
  check_input_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, 0}, "cannot open " + what);
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kInputSizeLimit)
      throw InputError({path, 0, 0}, "grew beyond " + megabytes(kInputSizeLimit) + " while it was read");
  }
  return text;
}

}  // namespace nhc
