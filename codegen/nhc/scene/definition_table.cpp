#include "nhc/scene/definition_table.hpp"

namespace nhc {

namespace {

std::string quoted_text(const std::string& text) {
  return text.size() <= 60 ? text : text.substr(0, 60) + "...";
}

}  // namespace

void DefinitionTable::add(const std::string& name, std::string text, Locator locate) {
  entries_[name] = Entry{std::move(text), std::move(locate), std::nullopt, false, {}};
}

ExpressionRules DefinitionTable::rules_with_definitions(ExpressionRules rules) {
  rules.definition = [this](const std::string& name) { return resolve(name); };
  return rules;
}

std::optional<Value> DefinitionTable::resolve(const std::string& name) {
  const auto it = entries_.find(name);
  if (it == entries_.end()) return std::nullopt;
  Entry& entry = it->second;
  if (resolving_.empty()) used_from_outside_.insert(name);
  else entries_.at(resolving_.back()).uses.insert(name);
  if (entry.value) return entry.value;
  if (entry.in_progress) {
    std::string chain;
    bool inside = false;
    for (const std::string& n : resolving_) {
      inside = inside || n == name;
      if (inside) chain += n + " -> ";
    }
    throw InputError(entry.locate(0), "definition '" + name + "' depends on itself (" + chain +
                                          name + ")");
  }
  entry.in_progress = true;
  resolving_.push_back(name);
  try {
    entry.value = parse_value(entry.text, jet_, rules_with_definitions(rules_));
  } catch (const ExpressionSyntaxError& e) {
    resolving_.pop_back();
    entry.in_progress = false;
    throw InputError(entry.locate(e.offset()), "in definition '" + name + "' \"" +
                                                   quoted_text(entry.text) + "\": " + e.what());
  } catch (...) {
    resolving_.pop_back();
    entry.in_progress = false;
    throw;
  }
  resolving_.pop_back();
  entry.in_progress = false;
  return entry.value;
}

void DefinitionTable::resolve_all() {
  for (auto& [name, entry] : entries_) {
    if (entry.value) continue;
    // Resolving it here is no use of it: an unused definition stays unused.
    const bool was_used = used_from_outside_.count(name) > 0;
    resolve(name);
    if (!was_used) used_from_outside_.erase(name);
  }
}

std::vector<std::pair<std::string, SourceLocation>> DefinitionTable::unused() const {
  std::set<std::string> reached;
  std::vector<std::string> stack(used_from_outside_.begin(), used_from_outside_.end());
  while (!stack.empty()) {
    const std::string name = stack.back();
    stack.pop_back();
    if (!reached.insert(name).second) continue;
    for (const std::string& next : entries_.at(name).uses) stack.push_back(next);
  }
  std::vector<std::pair<std::string, SourceLocation>> out;
  for (const auto& [name, entry] : entries_)
    if (!reached.count(name)) out.emplace_back(name, entry.locate(0));
  return out;
}

}  // namespace nhc
