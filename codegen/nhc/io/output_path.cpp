#include "nhc/io/output_path.hpp"

#include <sys/stat.h>

#include <filesystem>

#include "nhc/errors.hpp"

namespace nhc {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}

namespace {

void refuse_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs)
    if (!input.empty() && same_file(output, input))
      throw InputError({output, 0, 0}, "the output " + output + " is the input " + input +
                                           " (the same file); writing it would destroy the input: choose "
                                           "another output path");
}

/// The nearest existing ancestor of `path` must be a directory (`-o scene.toml/x.csv` is not).
void refuse_file_as_directory(const std::string& output, const fs::path& path) {
  for (fs::path p = path.parent_path(); !p.empty(); p = p.parent_path()) {
    struct stat s {};
    if (::stat(p.c_str(), &s) == 0) {
      if (!S_ISDIR(s.st_mode))
        throw InputError({output, 0, 0}, p.string() + " is a file, not a directory, so the output " + output +
                                             " cannot be created under it");
      return;
    }
    if (p == p.parent_path()) return;
  }
}

}  // namespace

OutputTarget output_target(const std::string& path) {
  fs::path p = path;
  for (int hops = 0;; ++hops) {
    struct stat s {};
    if (::lstat(p.c_str(), &s) != 0) {
      refuse_file_as_directory(path, p);
      return {p.string(), OutputTarget::Kind::new_file};
    }
    if (S_ISLNK(s.st_mode)) {
      // A link to a pipe or terminal (/dev/stdout, /proc/self/fd/1) names no file to follow to:
      // what it leads to is written through the link itself.
      struct stat end {};
      if (::stat(p.c_str(), &end) == 0 && (S_ISCHR(end.st_mode) || S_ISFIFO(end.st_mode)))
        return {p.string(), OutputTarget::Kind::stream};
      if (hops == 40) throw InputError({path, 0, 0}, "the output " + path + " is a loop of symbolic links");
      std::error_code ec;
      const fs::path link = fs::read_symlink(p, ec);
      if (ec) throw InputError({path, 0, 0}, "cannot read the symbolic link " + p.string() + ": " + ec.message());
      p = link.is_absolute() ? link : p.parent_path() / link;
      continue;
    }
    if (S_ISREG(s.st_mode)) return {p.string(), OutputTarget::Kind::regular};
    if (S_ISCHR(s.st_mode) || S_ISFIFO(s.st_mode)) return {p.string(), OutputTarget::Kind::stream};
    if (S_ISDIR(s.st_mode))
      throw InputError({path, 0, 0}, "the output " + path + " is a directory; a file name is expected");
    throw InputError({path, 0, 0}, "the output " + path + " is " +
                                       (S_ISBLK(s.st_mode) ? "a block device" : S_ISSOCK(s.st_mode) ? "a socket" : "not a regular file") +
                                       "; nhc writes outputs only to regular files, character devices and FIFOs");
  }
}

void check_output_file(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  output_target(output);
}

void check_output_directory(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  std::error_code ec;
  if (fs::exists(output, ec) && !fs::is_directory(output, ec))
    throw InputError({output, 0, 0}, "the output " + output + " exists and is not a directory");
  refuse_file_as_directory(output, fs::path(output));
}

}  // namespace nhc
