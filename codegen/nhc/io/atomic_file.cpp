#include "nhc/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

std::string temporary_name_for(const std::string& path) {
  std::random_device rd;
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(rd() % 1000000);
}

}  // namespace

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  const std::string temporary = temporary_name_for(path);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError({path, 0, 0}, std::string("cannot write: ") + std::strerror(errno));
    try {
      write(out);
      out.flush();
      if (!out) throw InputError({path, 0, 0}, "write failed (disk full?)");
    } catch (...) {
      out.close();
      std::remove(temporary.c_str());
      throw;
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw InputError({path, 0, 0}, "cannot write: " + reason);
  }
}

}  // namespace nhc
