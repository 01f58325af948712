#pragma once
/// \file printable.hpp
/// \brief Text from a file shown in a message: control characters (a NUL byte, an escape
/// sequence, a line break) are written as \xNN, so that a message is one line and never carries
/// raw bytes of the input to the terminal.

#include <string>

namespace nhc {

/// `text` with every byte below 0x20 and 0x7f written as \xNN (\t, \n, \r as themselves escaped).
std::string printable(const std::string& text);

}  // namespace nhc
