// Scene texts rewritten (scene.hpp, scene_text.hpp): the system's text, a switched model's, the
// [inputs] laws written in place.
#include "nhc/scene/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <iostream>

#include <fmt/format.h>

#include "nhc/io/input_file.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/work_budget.hpp"
#include "nhc/scene/definition_table.hpp"
#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/tolerances.hpp"
#include "nhc/scene/toml_text_check.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/expr/zero_test.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/scene_text.hpp"

namespace nhc {

using scene_reading::looks_like_multiplier;

std::string switched_source(const std::string& text, const std::set<int>& removed,
                            const std::map<std::string, std::string>& added_forces) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error&) {
    return text;
  }
  for (const char* table :
       {"contacts", "events", "outputs", "invariants", "reference", "visual", "optimize", "controller"})
    root.erase(table);
  if (toml::array* constraints = root["constraints"].as_array()) {
    toml::array kept;
    for (std::size_t k = 0; k < constraints->size(); ++k)
      if (!removed.count(static_cast<int>(k))) kept.push_back(*(*constraints)[k].as_string());
    if (kept.empty()) root.erase("constraints");
    else root.insert_or_assign("constraints", kept);
  }
  root.erase("dependent");  // one per constraint: the suslov model's, not the switched model's
  if (toml::table* initial = root["initial"].as_table()) {
    std::vector<std::string> multipliers;
    for (auto&& [key, value] : *initial)
      if (looks_like_multiplier(std::string(key.str()))) multipliers.emplace_back(key.str());
    for (const std::string& key : multipliers) initial->erase(key);  // guesses; the run's own values follow
  }
  if (!added_forces.empty()) {
    if (!root.contains("forces")) root.insert("forces", toml::table{});
    toml::table& forces = *root["forces"].as_table();
    for (const auto& [coordinate, force] : added_forces) {
      const toml::node* old = forces.get(coordinate);
      const std::string sum =
          old && old->is_string() ? "(" + *old->value<std::string>() + ") + (" + force + ")" : force;
      forces.insert_or_assign(coordinate, sum);
    }
  }
  std::ostringstream out;
  out << toml::toml_formatter(root);
  return out.str();
}

std::string equations_source(const std::string& text) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error&) {
    return text;
  }
  root.erase("initial");
  root.erase("simulate");
  root.erase("optimize");    // steers nhc optimize, not part of the equations
  root.erase("visual");      // drawn from the run, not part of the equations
  root.erase("events");      // located along the run, not part of the equations
  root.erase("contacts");    // forces read from the multipliers along the run
  root.erase("controller");  // sets the inputs along the run, not part of the equations
  root.erase("outputs");     // sampled from the run, not part of the equations
  std::ostringstream out;
  out << toml::toml_formatter(root);
  return out.str();
}

std::string scene_text_with_inputs(const std::string& text, const std::map<std::string, std::string>& laws) {
  const toml::table root = toml::parse(text);
  // Each entry's value replaced in place, the last in the text first, so that every other line
  // and column of the file (its messages' locations) stays where it was.
  std::vector<std::pair<std::size_t, std::pair<std::size_t, std::string>>> edits;
  std::vector<std::size_t> line_start{0};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') line_start.push_back(i + 1);
  const auto offset = [&](const toml::source_position& at) {
    return line_start.at(static_cast<std::size_t>(at.line) - 1) + static_cast<std::size_t>(at.column) - 1;
  };
  const toml::table* inputs = root["inputs"].as_table();
  for (const auto& [name, law] : laws) {
    const toml::node* node = inputs ? inputs->get(name) : nullptr;
    if (!node) throw std::invalid_argument("the scene has no input '" + name + "'");
    if (law.find_first_of("\"\\\n") != std::string::npos)
      throw std::invalid_argument("the law of '" + name + "' holds a quote, backslash or line break");
    const std::size_t begin = offset(node->source().begin), end = offset(node->source().end);
    edits.push_back({begin, {end, "\"" + law + "\""}});
  }
  std::sort(edits.begin(), edits.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out = text;
  for (const auto& [begin, edit] : edits) out.replace(begin, edit.first - begin, edit.second);
  return out;
}

bool scene_gives_t_end(const std::string& text) { return toml::parse(text)["simulate"]["t_end"].node() != nullptr; }

std::set<std::string> scene_definition_names(const std::string& text) {
  std::set<std::string> names;
  if (const toml::table* definitions = toml::parse(text)["definitions"].as_table())
    for (const auto& [key, value] : *definitions) names.insert(std::string(key.str()));
  return names;
}

}  // namespace nhc
