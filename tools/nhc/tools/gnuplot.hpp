#pragma once
/// \file gnuplot.hpp
/// \brief The one way nhc hands text to gnuplot and runs it. Names read from files (scenes,
/// ensemble files, file names) reach gnuplot scripts only through gnuplot_string(), whose value
/// is the text itself: gnuplot expands backquotes (a shell command) and `@` macros on a script
/// line, and inside double-quoted strings, but nothing inside single-quoted ones (docs/safety.md).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace nhc::tools {

/// A gnuplot string expression whose value is exactly `text`: single-quoted pieces (a quote
/// doubled) joined by `.` with octal escapes for control characters, in parentheses, so that it
/// stands wherever gnuplot takes a string (set output, set title, plot 'file', title).
/// A NUL byte, which no gnuplot string can hold, is written as the four characters `\000`.
std::string gnuplot_string(const std::string& text);

/// A comment line of a gnuplot script ("# text\n"): control characters shown as \ooo and a
/// trailing backslash (which would continue the comment onto the next line) followed by a space.
std::string gnuplot_comment(const std::string& text);

/// Why gnuplot cannot be run (with the Debian package that provides it), or nothing when it can.
std::optional<std::string> gnuplot_missing();

/// Runs gnuplot on `scripts` (file names in `directory`, one after another in one process) with
/// `directory` as its working directory, without a shell; an interrupt stops it
/// (subprocess.hpp). Returns its exit status (-1 when it could not be started or was killed) and
/// appends what it printed to `messages`.
int run_gnuplot(const std::filesystem::path& directory, const std::vector<std::string>& scripts, std::string& messages);

}  // namespace nhc::tools
