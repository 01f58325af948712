#include "nhc/scene/toml_text_check.hpp"

namespace nhc {

namespace {

bool starts_with(std::string_view text, std::size_t at, std::string_view prefix) {
  return text.substr(at, prefix.size()) == prefix;
}

/// The UTF-8 sequence starting at `at` (its lead byte and continuation bytes).
std::string character_at(std::string_view text, std::size_t at) {
  std::size_t end = at + 1;
  while (end < text.size() && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80 && end - at < 4) ++end;
  return std::string(text.substr(at, end - at));
}

/// The length of the closing delimiter of a multi-line string at `at`: three quotes and up to two
/// more that belong to the content ("""a""""" ends after five); 0 when none starts there.
std::size_t closing_run(std::string_view text, std::size_t at, char quote) {
  std::size_t quotes = 0;
  while (quotes < 5 && at + quotes < text.size() && text[at + quotes] == quote) ++quotes;
  return quotes >= 3 ? quotes : 0;
}

}  // namespace

std::optional<TextCharacter> non_ascii_outside_strings(std::string_view toml) {
  enum class In { text, comment, basic, literal, multiline_basic, multiline_literal } in = In::text;
  int line = 1, column = 0;
  for (std::size_t i = 0; i < toml.size(); ++i) {
    const char c = toml[i];
    const bool continuation = (static_cast<unsigned char>(c) & 0xC0) == 0x80;
    if (c == '\n') {
      ++line;
      column = 0;
      if (in == In::comment || in == In::basic || in == In::literal) in = In::text;  // unterminated: toml++ says so
      continue;
    }
    if (!continuation) ++column;
    switch (in) {
      case In::text:
        if (static_cast<unsigned char>(c) >= 0x80) return TextCharacter{line, column, character_at(toml, i)};
        if (c == '#') in = In::comment;
        else if (starts_with(toml, i, "\"\"\"")) in = In::multiline_basic, i += 2, column += 2;
        else if (starts_with(toml, i, "'''")) in = In::multiline_literal, i += 2, column += 2;
        else if (c == '"') in = In::basic;
        else if (c == '\'') in = In::literal;
        break;
      case In::comment: break;
      case In::basic:
        if (c == '\\' && i + 1 < toml.size() && toml[i + 1] != '\n') ++i, ++column;  // an escaped character
        else if (c == '"') in = In::text;
        break;
      case In::literal:
        if (c == '\'') in = In::text;
        break;
      case In::multiline_basic:
      case In::multiline_literal: {
        const bool basic = in == In::multiline_basic;
        if (basic && c == '\\' && i + 1 < toml.size() && toml[i + 1] != '\n') {
          ++i, ++column;  // an escaped character
        } else if (const std::size_t quotes = closing_run(toml, i, basic ? '"' : '\''); quotes > 0) {
          i += quotes - 1;
          column += static_cast<int>(quotes) - 1;
          in = In::text;
        }
        break;
      }
    }
  }
  return std::nullopt;
}

std::optional<TextCharacter> control_character(std::string_view toml) {
  int line = 1, column = 0;
  for (std::size_t i = 0; i < toml.size(); ++i) {
    const auto c = static_cast<unsigned char>(toml[i]);
    if (c == '\n') {
      ++line;
      column = 0;
      continue;
    }
    if ((c & 0xC0) != 0x80) ++column;
    const bool line_end = c == '\r' && i + 1 < toml.size() && toml[i + 1] == '\n';
    if ((c < 0x20 && c != '\t' && !line_end) || c == 0x7F)
      return TextCharacter{line, column, std::string(1, static_cast<char>(c))};
  }
  return std::nullopt;
}

}  // namespace nhc
