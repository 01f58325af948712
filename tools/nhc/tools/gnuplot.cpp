// Quoting for gnuplot and the one place gnuplot is run (gnuplot.hpp).
#include "nhc/tools/gnuplot.hpp"

#include "nhc/tools/subprocess.hpp"

namespace nhc::tools {

namespace {

/// `\ooo`: the octal escape of one byte.
std::string octal(unsigned char c) {
  const char digits[] = {'\\', static_cast<char>('0' + (c >> 6)), static_cast<char>('0' + ((c >> 3) & 7)),
                         static_cast<char>('0' + (c & 7)), 0};
  return digits;
}

bool control(unsigned char c) { return c < 0x20 || c == 0x7f; }

}  // namespace

std::string gnuplot_string(const std::string& text) {
  // Single-quoted gnuplot strings expand nothing (no backquotes, no macros, no escapes); only a
  // quote, doubled, and a line break, which would end the command, need care. Control characters
  // are double-quoted pieces holding nothing but an octal escape.
  std::string q = "('";
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == 0) q += "\\000";
    else if (control(c)) q += "'.\"" + octal(c) + "\".'";
    else if (ch == '\'') q += "''";
    else q += ch;
  }
  return q + "')";
}

std::string gnuplot_comment(const std::string& text) {
  std::string line = "# ";
  for (char ch : text)
    line += control(static_cast<unsigned char>(ch)) ? octal(static_cast<unsigned char>(ch)) : std::string(1, ch);
  if (line.back() == '\\') line += ' ';
  return line + "\n";
}

std::optional<std::string> gnuplot_missing() {
  std::string output;
  if (run_process({"gnuplot", "--version"}, output) == 0) return std::nullopt;
  return "gnuplot cannot be run (Debian package gnuplot-nox; scripts/setup.sh installs it)";
}

int run_gnuplot(const std::filesystem::path& directory, const std::vector<std::string>& scripts,
                std::string& messages) {
  // The directory and the script names are arguments of sh, never part of its program text.
  std::vector<std::string> argv{"sh", "-c", "cd -- \"$0\" && exec gnuplot \"$@\"",
                                directory.empty() ? std::string(".") : directory.string()};
  for (const std::string& script : scripts) argv.push_back("./" + script);  // a name starting with '-' is no option
  return run_process(argv, messages);
}

}  // namespace nhc::tools
