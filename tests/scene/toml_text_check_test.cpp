// The check of a scene's text before toml++ reads it (toml_text_check.hpp): every class of code
// points beyond ASCII where toml++ 3.3 would ask whether it is whitespace (after a value, a key, a
// bracket, inside a bare value holding a quote, after a backslash in a multi-line string) is
// refused at its line and column; inside strings and comments it reaches toml++ and the scene.
// The same family is in the fuzz corpus (tests/fuzz/non_ascii_family.py), replayed under UBSan.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/toml_text_check.hpp"

namespace {

std::string utf8(char32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else if (c < 0x10000) {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (c >> 18));
    s += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}

// The classes of toml++ 3.3's is_non_ascii_horizontal_whitespace: NEL, NBSP, the first and last of
// each block where it is undefined (U+00A1…U+0499, U+2C5E…U+2FFF, U+3001…U+3057, U+FB26…U+FEFE),
// the spaces it knows, the byte order mark, and beyond it.
const std::vector<char32_t> kCodePoints = {0x85,   0xA0,   0xA1,   0x27E,  0x3BB,  0x499,  0x1680,
                                           0x2000, 0x2028, 0x2C5E, 0x2FFF, 0x3000, 0x3001, 0x3057,
                                           0xFB26, 0xFEFE, 0xFEFF, 0xFF21, 0x1F600};

const char* kHead =
    "name = \"non_ascii\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2 - k*x^2/2\"\n"
    "[parameters]\nk = 1.0\n";  // five lines

struct Place {
  const char* name;
  const char* text;  // after kHead; @ stands for the character
  bool refused;
};

const std::vector<Place> kPlaces = {
    {"after a number", "c = 1@\n", true},
    {"after a quote inside a number", "c = 0\"t@\"\n", true},
    {"after a quote inside a date", "c = 1979-05-27\"@\"\n", true},
    {"after a sign", "c = -\"@\"\n", true},
    {"after a string", "c = \"1\"@\n", true},
    {"after a second string", "c = \"1\" \"@\"\n", true},
    {"after a boolean", "c = true@\n", true},
    {"after a quote inside a boolean", "c = t\"@\"\n", true},
    {"after a key", "c@ = 1\n", true},
    {"after a key and a space", "c @ = 1\n", true},
    {"after a quote inside a key", "c\"@\" = 1\n", true},
    {"after a dot in a key", "c.@ = 1\n", true},
    {"after a dot in a number", "c = 1.\"@\"\n", true},
    {"after a header's bracket", "[@]\n", true},
    {"after a header", "[initial]@\n", true},
    {"after an array's bracket", "c = [@]\n", true},
    {"after an array's comma", "c = [1,@]\n", true},
    {"after an array", "c = [1]\"@\"\n", true},
    {"after a brace", "c = {@}\n", true},
    {"after an inline table", "c = {a = 1}\"@\"\n", true},
    {"after a backslash in a multi-line string", "c = \"\"\"\\@\"\"\"\n", true},
    {"after a backslash and spaces in a multi-line string", "c = \"\"\"\\  @\"\"\"\n", true},
    {"after a line-ending backslash", "c = \"\"\"\\\n  @\"\"\"\n", true},
    {"after a line-ending backslash and empty lines", "c = \"\"\"\\\n\n\t@\"\"\"\n", true},
    {"in a comment", "# @\n", false},
    {"in a comment after a value", "c = 1 # @\n", false},
    {"in a string", "c = \"1@\"\n", false},
    {"in a string after an escaped quote", "c = \"\\\"@\"\n", false},
    {"in a literal string", "c = '1@'\n", false},
    {"in a multi-line string", "c = \"\"\"\n1@\"\"\"\n", false},
    {"in a multi-line string after an escape", "c = \"\"\"\\n@\"\"\"\n", false},
    {"in a multi-line string after a continued line", "c = \"\"\"\\\n  1@\"\"\"\n", false},
    {"in a multi-line literal string", "c = '''1@'''\n", false},
    {"in a quoted key", "\"c@\" = 1\n", false},
    {"in a dotted quoted key", "c . \"@\" = 1\n", false},
    {"in a quoted key of a header", "[\"@\"]\n", false},
    {"in a quoted key of an array of tables", "[[\"@\"]]\n", false},
    {"in an array's string", "c = [1, \"@\"]\n", false},
    {"in an array's string after a comment and a line end", "c = [ # x\n  \"@\" ]\n", false},
    {"in a nested array's string", "c = [[1], [\"@\"]]\n", false},
    {"in an inline table's key", "c = { \"@\" = 1 }\n", false},
    {"in an inline table's value", "c = { a = [1], b = \"@\" }\n", false},
};

/// The line and column (code points) of '@' in kHead + text.
std::pair<int, int> position_of_mark(const std::string& text) {
  int line = 6, column = 1;
  for (char c : text) {
    if (c == '@') break;
    if (c == '\n') ++line, column = 1;
    else ++column;
  }
  return {line, column};
}

std::string with(const std::string& text, char32_t c) {
  std::string out = kHead;
  for (char ch : text) out += ch == '@' ? utf8(c) : std::string(1, ch);
  return out;
}

}  // namespace

TEST_CASE("every non-ASCII class is refused where toml++ would classify it, at its line and column",
          "[scene][loader][toml]") {
  for (const Place& place : kPlaces) {
    if (!place.refused) continue;
    const auto [line, column] = position_of_mark(place.text);
    for (char32_t c : kCodePoints) {
      const std::string text = with(place.text, c);
      INFO(place.name << ", U+" << std::hex << static_cast<unsigned>(c) << ":\n" << text);
      const std::optional<nhc::MisplacedCharacter> m = nhc::misplaced_non_ascii(text);
      REQUIRE(m);
      CHECK(m->character.line == line);
      CHECK(m->character.column == column);
      CHECK(m->character.text == utf8(c));
      CHECK(m->after_backslash == (std::string(place.name).find("backslash") != std::string::npos));
      try {
        nhc::parse_scene(text, "s.toml");
        FAIL("loaded");
      } catch (const nhc::InputError& e) {
        CHECK(e.where().line == line);
        CHECK(e.where().column == column);
        CHECK_THAT(e.what(), Catch::Contains("TOML syntax: '"));
      }
    }
  }
}

TEST_CASE("non-ASCII inside strings and comments reaches toml++ and the scene", "[scene][loader][toml]") {
  for (const Place& place : kPlaces) {
    if (place.refused) continue;
    for (char32_t c : kCodePoints) {
      const std::string text = with(place.text, c);
      INFO(place.name << ", U+" << std::hex << static_cast<unsigned>(c) << ":\n" << text);
      CHECK_FALSE(nhc::misplaced_non_ascii(text));
      // Loaded, or refused by the scene's own rules (a parameter that is a string or a table,
      // a name beyond [A-Za-z_]…), never by the check of the text.
      try {
        nhc::parse_scene(text, "s.toml");
      } catch (const nhc::InputError& e) {
        CHECK_THAT(e.what(), !Catch::Contains("outside a string") && !Catch::Contains("after a backslash"));
      }
    }
  }
  // A comment and a string the scene reads keep their characters.
  const nhc::Scene scene = nhc::parse_scene(with("# λ, 中, 😀 @\n", 0x3BB), "s.toml");
  CHECK(scene.name == "non_ascii");
}

TEST_CASE("the fuzzer's input with a quote inside a number is refused at its character", "[scene][loader][toml]") {
  // scene-crash-19537029…: n=0"trg~7…7ɾ7…: toml++ scans the value 0"trg~… to its end, asking of
  // ɾ (U+027E) whether it is whitespace: __builtin_unreachable in is_non_ascii_horizontal_whitespace.
  const std::string text = "n=0\"trg~" + std::string(24, '7') + "\xC9\xBE" + std::string(8, '7') + "\"]";
  try {
    nhc::parse_scene(text, "s.toml");
    FAIL("loaded");
  } catch (const nhc::InputError& e) {
    CHECK(e.where().line == 1);
    CHECK(e.where().column == 33);
    CHECK_THAT(e.what(), Catch::Contains("'\xC9\xBE' outside a string or comment"));
  }
}
