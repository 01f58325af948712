#include "nhc/io/output_path.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <utility>

#include "nhc/errors.hpp"

namespace nhc {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
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

/// The stream outputs opened by check_output_file(), by device and inode (one file under any
/// name), until the write takes them; a process writes few outputs, so they are never pruned.
struct HeldOutputs {
  std::mutex mutex;
  std::map<std::pair<dev_t, ino_t>, int> descriptors;
};

HeldOutputs& held_outputs() {
  static HeldOutputs held;
  return held;
}

/// Opens `device` and holds it, unless a descriptor on the same file is held already.
void hold_stream_output(const std::string& path, const std::string& device) {
  struct stat s {};
  HeldOutputs& held = held_outputs();
  const std::lock_guard<std::mutex> lock(held.mutex);
  if (::stat(device.c_str(), &s) == 0 && held.descriptors.count({s.st_dev, s.st_ino}) != 0) return;
  const int fd = open_stream_output(path, device);
  if (::fstat(fd, &s) != 0) {
    ::close(fd);
    throw EnvironmentError("cannot write " + path + ": " + std::strerror(errno));
  }
  held.descriptors[{s.st_dev, s.st_ino}] = fd;
}

}  // namespace

int open_stream_output(const std::string& path, const std::string& device) {
  // O_NONBLOCK: opening a FIFO for writing without a reader fails (ENXIO) instead of waiting.
  const int fd = ::open(device.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errno == ENXIO)
      throw InputError({path, 0, 0}, "the output " + path + " is a FIFO that nobody reads; start its reader first");
    throw EnvironmentError("cannot write " + path + ": " + std::strerror(errno));
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  return fd;
}

int take_held_output(const std::string& device) {
  struct stat s {};
  if (::stat(device.c_str(), &s) != 0) return -1;
  HeldOutputs& held = held_outputs();
  const std::lock_guard<std::mutex> lock(held.mutex);
  const auto found = held.descriptors.find({s.st_dev, s.st_ino});
  if (found == held.descriptors.end()) return -1;
  const int fd = found->second;
  held.descriptors.erase(found);
  return fd;
}

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
                                       (S_ISBLK(s.st_mode)    ? "a block device"
                                        : S_ISSOCK(s.st_mode) ? "a socket"
                                                              : "not a regular file") +
                                       "; nhc writes outputs only to regular files, character devices and FIFOs");
  }
}

void check_output_file(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  const OutputTarget target = output_target(output);
  if (target.kind == OutputTarget::Kind::stream) hold_stream_output(output, target.path);
}

void check_output_directory(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  std::error_code ec;
  if (fs::exists(output, ec) && !fs::is_directory(output, ec))
    throw InputError({output, 0, 0}, "the output " + output + " exists and is not a directory");
  refuse_file_as_directory(output, fs::path(output));
}

}  // namespace nhc
