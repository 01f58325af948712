// libFuzzer target: arbitrary bytes as a scene file. Every input must either load or be
// rejected with nhc::InputError; anything else (a crash, another exception, a sanitizer
// report) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nhc/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    nhc::parse_scene(text, "fuzz.toml");
  } catch (const nhc::InputError&) {
  }
  return 0;
}
