#include "nhc/scene/scene_visual.hpp"

#include <array>

namespace nhc {

namespace {

using K = VisualValueKind;

struct ShapeEntry {
  VisualShape shape;
  const char* name;
  std::vector<VisualKey> keys;
};

const std::array<ShapeEntry, 6>& shapes() {
  static const std::array<ShapeEntry, 6> table{{
      {VisualShape::sphere,
       "sphere",
       {{"radius", K::scalar, true}, {"center", K::vector, true}, {"rotation", K::rotation, false}}},
      {VisualShape::cylinder,
       "cylinder",
       {{"radius", K::scalar, true},
        {"length", K::scalar, true},
        {"center", K::vector, true},
        {"rotation", K::rotation, false}}},
      {VisualShape::box,
       "box",
       {{"size", K::vector, true}, {"center", K::vector, true}, {"rotation", K::rotation, false}}},
      {VisualShape::segment, "segment", {{"from", K::vector, true}, {"to", K::vector, true}}},
      {VisualShape::trace, "trace", {{"point", K::vector, true}}},
      {VisualShape::plane, "plane", {{"size", K::scalar, false}}},
  }};
  return table;
}

}  // namespace

const std::vector<VisualKey>& visual_keys(VisualShape shape) {
  for (const ShapeEntry& entry : shapes())
    if (entry.shape == shape) return entry.keys;
  return shapes()[0].keys;
}

std::optional<VisualShape> parse_visual_shape(const std::string& name) {
  for (const ShapeEntry& entry : shapes())
    if (name == entry.name) return entry.shape;
  return std::nullopt;
}

const char* to_string(VisualShape shape) {
  for (const ShapeEntry& entry : shapes())
    if (entry.shape == shape) return entry.name;
  return "?";
}

std::string visual_shape_names() {
  std::string names;
  for (const ShapeEntry& entry : shapes()) names += (names.empty() ? "" : ", ") + std::string(entry.name);
  return names;
}

}  // namespace nhc
