#include "nhc/io/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "nhc/errors.hpp"
#include "nhc/io/temporary_files.hpp"

namespace nhc {

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  // Registered before it exists: an interrupt at any moment removes it (temporary_files.hpp).
  const TemporaryFile registration(unique_temporary_name(path));
  const std::string& temporary = registration.path();
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
