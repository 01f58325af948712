#include "animation_page.hpp"

#include "nhc/base/number_text.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"

namespace nhc::cli {

namespace {

/// Nine significant digits: a page, not an archive (the CSV of nhc simulate has 17).
void write_number(std::ostream& out, double v) {
  if (!std::isfinite(v)) {
    out << "null";
    return;
  }
  out << base::number_text(v, 9);
}

/// The sample times in full (the shortest text that reads back as the same double): with 9 digits,
/// t0 = 1e6 made 1001 samples 0.01 apart 101 distinct times, a staircase on the page.
void write_times(std::ostream& out, const std::vector<double>& values) {
  out << '[';
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out << ',';
    if (std::isfinite(values[i])) out << base::shortest_text(values[i]);
    else out << "null";
  }
  out << ']';
}

void write_numbers(std::ostream& out, const std::vector<double>& values) {
  out << '[';
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out << ',';
    write_number(out, values[i]);
  }
  out << ']';
}

/// A JSON string (the names are identifiers, but the scene name is copied as it is).
void write_string(std::ostream& out, const std::string& s) {
  out << '"';
  for (const char c : s) {
    if (c == '"' || c == '\\') out << '\\' << c;
    else if (c == '<') out << "\\u003c";  // never "</script>" inside the page's script
    else if (static_cast<unsigned char>(c) < 0x20) out << ' ';
    else out << c;
  }
  out << '"';
}

std::string content_json(const AnimationContent& content) {
  std::ostringstream out;
  out << "{\"scene\":";
  write_string(out, content.scene_name);
  out << ",\"model\":";
  write_string(out, content.model_name);
  out << ",\n\"t\":";
  write_times(out, content.times);
  out << ",\n\"visuals\":[";
  for (std::size_t k = 0; k < content.tracks.size(); ++k) {
    const VisualTrack& track = content.tracks[k];
    const SceneVisual& v = *track.visual;
    out << (k ? ",\n" : "\n") << "{\"name\":";
    write_string(out, v.name);
    out << ",\"shape\":\"" << to_string(v.shape) << "\",\"color\":";
    write_string(out, v.color);
    out << ",\"opacity\":";
    write_number(out, v.opacity);
    out << ",\"axis\":" << v.axis << ",\"radius\":";
    write_number(out, track.radius);
    out << ",\"length\":";
    write_number(out, track.length);
    if (v.shape == VisualShape::plane) {
      out << ",\"size\":";
      if (track.size.empty()) out << "null";
      else write_number(out, track.size[0]);
    } else if (!track.size.empty()) {
      out << ",\"size\":";
      write_numbers(out, track.size);
    }
    if (!track.position.empty()) out << ",\n\"position\":", write_numbers(out, track.position);
    if (!track.to.empty()) out << ",\n\"to\":", write_numbers(out, track.to);
    out << ",\n\"rotation\":";
    if (track.rotation.empty()) out << "null";
    else write_numbers(out, track.rotation);
    out << '}';
  }
  out << "]}";
  return out.str();
}

void copy_file_to(const std::filesystem::path& from, const std::string& to) {
  std::error_code ec;
  if (!std::filesystem::copy_file(from, to, std::filesystem::copy_options::overwrite_existing, ec))
    throw EnvironmentError("cannot copy " + from.string() + " to " + to + ": " + ec.message());
}

}  // namespace

std::string animation_page(const AnimationContent& content) {
  std::string page = animation_page_template();
  const std::string placeholder = "/*NHC_DATA*/";
  const std::size_t at = page.find(placeholder);
  if (at == std::string::npos) throw std::logic_error("the animation page template has no data placeholder");
  return page.replace(at, placeholder.size(), content_json(content));
}

void write_animation_page(const std::string& directory, const AnimationContent& content,
                          const std::vector<std::string>& inputs) {
  const std::filesystem::path three_dir = NHC_THREE_JS_DIR;
  const std::filesystem::path three = three_dir / "build" / "three.min.js";
  const std::filesystem::path orbit = three_dir / "examples" / "js" / "controls" / "OrbitControls.js";
  for (const std::filesystem::path& file : {three, orbit})
    if (!std::filesystem::is_regular_file(file))
      throw EnvironmentError("nhc animate needs three.js: " + file.string() +
                             " is missing (install Debian's libjs-three: apt-get install libjs-three)");
  AtomicDirectory out(directory, inputs);
  {
    std::ofstream page(out.file("index.html"), std::ios::binary);
    page << animation_page(content);
    if (!page.flush()) throw EnvironmentError("cannot write " + out.final_file("index.html"));
  }
  copy_file_to(three, out.file("three.min.js"));
  copy_file_to(orbit, out.file("OrbitControls.js"));
  out.commit();
}

}  // namespace nhc::cli
