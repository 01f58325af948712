#pragma once
/// \file input_file.hpp
/// \brief Reading has limits (docs/safety.md): a file nhc reads as data — a scene, an --input
/// CSV, an ensemble's .h5 — must be a regular file (a link to one is fine), and a text file at
/// most kInputSizeLimit bytes; anything else is refused in one line naming it, before a byte is
/// read (/dev/zero, a FIFO, a directory would otherwise be read forever, wait, or read as empty).

#include <cstdint>
#include <string>

namespace nhc {

/// The largest scene or CSV file nhc reads: 64 MiB (a 10^6-row input series is about 40 MB).
inline constexpr std::uintmax_t kInputSizeLimit = std::uintmax_t{64} << 20;

/// Throws InputError at `path` unless it is a regular file of at most `limit` bytes; `what` names
/// what was expected ("a scene file", "a CSV file") in the message.
void check_input_file(const std::string& path, const std::string& what, std::uintmax_t limit = kInputSizeLimit);

/// check_input_file(), then the whole file (read up to the limit, should it grow meanwhile).
/// Throws InputError when it cannot be opened.
std::string read_input_file(const std::string& path, const std::string& what);

}  // namespace nhc
