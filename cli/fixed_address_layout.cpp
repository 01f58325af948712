#include "fixed_address_layout.hpp"

#include <sys/personality.h>
#include <unistd.h>

namespace nhc::cli {

void run_with_fixed_address_layout(char** argv) {
  const int current = personality(0xffffffff);  // query only
  if (current == -1 || (current & ADDR_NO_RANDOMIZE) != 0) return;
  if (personality(static_cast<unsigned long>(current) | ADDR_NO_RANDOMIZE) == -1) return;
  execv("/proc/self/exe", argv);
  // exec failed: restore the layout setting for any child, go on in this process.
  personality(static_cast<unsigned long>(current));
}

}  // namespace nhc::cli
