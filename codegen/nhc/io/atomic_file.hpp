#pragma once
/// \file atomic_file.hpp
/// \brief Writing output files so that no half-written file is ever visible: the content goes
/// to a temporary file in the same directory, which is renamed over the target when complete.

#include <functional>
#include <ostream>
#include <string>

namespace nhc {

/// Calls `write` with a stream on a temporary file beside `path`, then renames it to `path`;
/// where `path` leads is decided by output_target() (output_path.hpp): the target of a symbolic
/// link is replaced and the link stays, a character device or FIFO is written in place.
/// On any exception the temporary file is removed and the exception propagates.
/// Throws EnvironmentError naming `path` and the system's reason when it cannot be written
/// (no permission, disk full, …).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace nhc
