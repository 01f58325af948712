#include "nhc/io/atomic_file.hpp"
#include "nhc/io/parent_directories.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/io/temporary_files.hpp"

namespace nhc {

namespace {

/// The system's reason for the last failure, or `fallback` when errno says nothing.
std::string system_reason(int error, const char* fallback) {
  return error != 0 ? std::string(std::strerror(error)) : std::string(fallback);
}

/// Forces the bytes to the device, so that a full disk is reported now and not lost at close.
int sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int status = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return status == EINVAL || status == EROFS ? 0 : status;  // files that cannot be synced (pipes, /dev)
}

}  // namespace

/// The temporary file beside `path`, written, synced and renamed over it.
static void write_into_existing_directory(const std::string& path, const std::function<void(std::ostream&)>& write);

/// A character device or a FIFO, written in place (output_path.hpp): never renamed over, through
/// the descriptor the output check holds (so the reader that was there then gets the bytes), or
/// opened now; a FIFO nobody reads is refused at once instead of waited on.
static void write_in_place(const std::string& path, const std::string& device,
                           const std::function<void(std::ostream&)>& write) {
  const int held = take_held_output(device);
  const int fd = held >= 0 ? held : open_stream_output(path, device);
  std::ostringstream text;
  try {
    write(text);
  } catch (...) {
    ::close(fd);
    throw;
  }
  const std::string bytes = text.str();
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = std::strerror(errno);
      ::close(fd);
      throw EnvironmentError("cannot write " + path + ": " + reason);
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::vector<std::string> created = create_missing_parents(path);
  try {
    const OutputTarget target = output_target(path);
    if (target.kind == OutputTarget::Kind::stream) write_in_place(path, target.path, write);
    else write_into_existing_directory(target.path, write);
  } catch (...) {
    remove_created_parents(created);
    throw;
  }
}

static void write_into_existing_directory(const std::string& path, const std::function<void(std::ostream&)>& write) {
  // Registered before it exists: an interrupt at any moment removes it (temporary_files.hpp).
  const TemporaryFile registration(unique_temporary_name(path));
  const std::string& temporary = registration.path();
  {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out)
      throw EnvironmentError("cannot write " + path + ": " + system_reason(errno, "cannot create a file there"));
    try {
      errno = 0;
      write(out);
      out.flush();
      if (!out) throw EnvironmentError("cannot write " + path + ": " + system_reason(errno, "write failed"));
      errno = 0;
      out.close();
      if (out.fail()) throw EnvironmentError("cannot write " + path + ": " + system_reason(errno, "write failed"));
      if (const int error = sync_file(temporary); error != 0)
        throw EnvironmentError("cannot write " + path + ": " + std::strerror(error));
    } catch (...) {
      out.close();
      std::remove(temporary.c_str());
      throw;
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw EnvironmentError("cannot write " + path + ": " + reason);
  }
}

}  // namespace nhc
