#include "nhc/scene/toml_text_check.hpp"

#include <vector>

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

std::optional<MisplacedCharacter> misplaced_non_ascii(std::string_view toml) {
  enum class In { text, comment, basic, literal, multiline_basic, multiline_literal } in = In::text;
  // After a backslash in a multi-line basic string: the escaped character comes next, or (a
  // line-ending backslash) spaces, tabs and line ends that toml++ skips asking of each whether
  // it is whitespace, up to the first other character, which it asks too.
  enum class Escape { none, next, skipping } escape = Escape::none;
  std::vector<char> nesting;    // the open arrays '[' and inline tables '{' of values, innermost last
  bool header = false;          // inside a table header, [a.b] or [[a.b]]
  std::size_t header_open = 0;  // where its first '[' is ([[ is one header)
  bool key_side = true;         // in a key (a line's start, a header, an inline table before '=')
  bool may_start = true;        // a key segment (key_side) or a value (else) may begin here
  int line = 1, column = 0;
  for (std::size_t i = 0; i < toml.size(); ++i) {
    const char c = toml[i];
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      ++line;
      column = 0;
      if (in == In::comment || in == In::basic || in == In::literal) in = In::text;  // unterminated: toml++ says so
      if (escape == Escape::next) escape = Escape::skipping;
      if (in == In::text && nesting.empty()) header = false, key_side = true, may_start = true;
      continue;
    }
    if ((u & 0xC0) != 0x80) ++column;
    const auto here = [&](bool after_backslash) {
      return MisplacedCharacter{TextCharacter{line, column, character_at(toml, i)}, after_backslash};
    };
    switch (in) {
      case In::text:
        if (u >= 0x80) return here(false);
        if (c == ' ' || c == '\t' || c == '\r') break;
        if (c == '#') {
          in = In::comment;
        } else if (c == '"' || c == '\'') {
          if (may_start) {
            const bool triple = starts_with(toml, i, c == '"' ? "\"\"\"" : "'''");
            in = c == '"' ? (triple ? In::multiline_basic : In::basic) : (triple ? In::multiline_literal : In::literal);
            if (triple) i += 2, column += 2;
          }
          may_start = false;  // after the string, or a quote inside a bare token such as 0"…
        } else if (c == '=' && key_side && !header) {
          key_side = false, may_start = true;
        } else if (c == '[' && !key_side && may_start) {
          nesting.push_back('[');
        } else if (c == '[' && key_side && may_start && nesting.empty() && !header) {
          header = true, header_open = i;
        } else if (c == '[' && header && i == header_open + 1) {
          // [[: an array of tables
        } else if (c == '{' && !key_side && may_start) {
          nesting.push_back('{');
          key_side = true;
        } else if (c == ']' && header) {
          header = false, may_start = false;  // a comment or the line's end follows
        } else if ((c == ']' || c == '}') && !nesting.empty() && nesting.back() == (c == ']' ? '[' : '{')) {
          nesting.pop_back();
          key_side = false, may_start = false;
        } else if (c == ',' && !nesting.empty()) {
          key_side = nesting.back() == '{', may_start = true;
        } else if (c == '.' && key_side) {
          may_start = true;
        } else {
          may_start = false;  // a bare key or value, or misplaced punctuation: toml++ refuses that
        }
        break;
      case In::comment:
        break;
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
        if (basic && escape != Escape::none) {
          if (u >= 0x80) return here(true);
          if (c == ' ' || c == '\t' || c == '\r') {
            escape = Escape::skipping;
            break;
          }
          const bool escaped = escape == Escape::next;
          escape = Escape::none;
          if (escaped) break;  // \", \\, \n …: not a delimiter
        }
        if (basic && c == '\\') {
          escape = Escape::next;
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
