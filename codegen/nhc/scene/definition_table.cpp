#include "nhc/scene/definition_table.hpp"

#include <algorithm>
#include <cctype>

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/jet_space.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

namespace {

std::string quoted_text(const std::string& text) { return text.size() <= 60 ? text : text.substr(0, 60) + "..."; }

}  // namespace

void DefinitionTable::add(const std::string& name, std::string text, Locator locate) {
  entries_[name] = Entry{std::move(text), std::move(locate), std::nullopt, false, {}};
}

ExpressionRules DefinitionTable::rules_with_definitions(ExpressionRules rules) {
  // Names that are not definitions go to the rules' own lookup (parameters computed from others).
  rules.definition = [this, outer = rules.definition](const std::string& name) -> std::optional<Value> {
    if (std::optional<Value> value = resolve(name)) return value;
    return outer ? outer(name) : std::nullopt;
  };
  return rules;
}

Value DefinitionTable::named(const std::string& name, Value value) {
  for (unsigned i = 0; i < value.rows; ++i)
    for (unsigned j = 0; j < value.cols; ++j) {
      GiNaC::ex& entry = value.entries[i * value.cols + j];
      entry = simplified_where_it_pays(entry);
      if (GiNaC::is_a<GiNaC::numeric>(entry) || GiNaC::is_a<GiNaC::symbol>(entry)) continue;
      if (expanded_nodes(entry, kSubstituteDefinitionBelowNodes) < kSubstituteDefinitionBelowNodes) {
        // Small: substituted, unless its expansion is not (kSubstituteDefinition…, intermediate.hpp).
        const GiNaC::ex substituted = expand_intermediates(entry);
        if (work_budget::expanded_terms(substituted) <= kSubstituteDefinitionMaxTerms) {
          entry = substituted;
          continue;
        }
      }
      std::string suffix;
      if (value.rows > 1) suffix += std::to_string(i + 1);
      if (value.cols > 1) suffix += std::to_string(j + 1);
      const std::string full = suffix.empty() ? name : name + "_" + suffix;
      // Printed as the coordinates are (jet_space.hpp): a multi-letter name upright, \mathrm{Tb},
      // so that it does not read as a product of letters.
      const std::string latex = jet_symbol_latex(name, VariableKind::coordinate, 0);
      entry = Intermediate(full, suffix.empty() ? latex : latex + "_{" + suffix + "}", entry);
    }
  return value;
}

std::optional<Value> DefinitionTable::resolve(const std::string& name) {
  const auto it = entries_.find(name);
  if (it == entries_.end()) return std::nullopt;
  Entry& entry = it->second;
  if (resolving_.empty()) used_from_outside_.insert(name);
  else entries_.at(resolving_.back()).uses.insert(name);
  if (entry.value) return entry.value;
  if (entry.in_progress) {
    std::vector<std::string> chain = resolving_;
    chain.push_back(name);
    cycle(chain);
  }
  entry.in_progress = true;
  resolving_.push_back(name);
  try {
    resolve_dependencies_first(name);
    entry.value = parse_value(entry.text, jet_, rules_with_definitions(rules_));
    if (keep_) entry.value = named(name, *entry.value);
  } catch (const ExpressionSyntaxError& e) {
    resolving_.pop_back();
    entry.in_progress = false;
    throw InputError(entry.locate(e.offset()),
                     "in definition '" + name + "' \"" + quoted_text(entry.text) + "\": " + e.what());
  } catch (...) {
    resolving_.pop_back();
    entry.in_progress = false;
    throw;
  }
  resolving_.pop_back();
  entry.in_progress = false;
  return entry.value;
}

std::vector<std::string> DefinitionTable::named_definitions(const std::string& text) const {
  std::vector<std::string> names;
  const auto name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t i = 0; i < text.size();) {
    if (std::isdigit(static_cast<unsigned char>(text[i]))) {  // a number whole: 1e5 names no e5
      while (i < text.size() && name_char(text[i])) ++i;
      continue;
    }
    if (!name_char(text[i])) {
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && name_char(text[end])) ++end;
    std::string name = text.substr(i, end - i);
    if (entries_.count(name) && std::find(names.begin(), names.end(), name) == names.end())
      names.push_back(std::move(name));
    i = end;
  }
  return names;
}

void DefinitionTable::resolve_dependencies_first(const std::string& root) {
  struct Frame {
    std::string name;
    std::vector<std::string> uses;
    std::size_t next = 0;
  };
  std::vector<Frame> stack;
  stack.push_back({root, named_definitions(entries_.at(root).text)});
  while (!stack.empty()) {
    Frame& frame = stack.back();
    if (frame.next < frame.uses.size()) {
      const std::string used = frame.uses[frame.next++];
      const Entry& entry = entries_.at(used);
      const auto on_stack = std::find_if(stack.begin(), stack.end(), [&](const Frame& f) { return f.name == used; });
      if (on_stack != stack.end()) {
        std::vector<std::string> chain = resolving_;
        chain.pop_back();  // root, the first frame
        for (auto f = stack.begin(); f != stack.end(); ++f) chain.push_back(f->name);
        chain.push_back(used);
        cycle(chain);
      }
      if (entry.value || entry.in_progress) continue;  // done, or resolving further out: the parse decides
      stack.push_back({used, named_definitions(entry.text)});
      continue;
    }
    const std::string done = frame.name;
    stack.pop_back();
    if (done != root) resolve(done);  // what it uses is resolved: one level deep
  }
}

void DefinitionTable::cycle(const std::vector<std::string>& chain) const {
  const std::string& name = chain.back();
  std::size_t first = 0;
  while (chain[first] != name) ++first;
  // A long cycle is shown by its ends: the message stays one readable line.
  constexpr std::size_t kShownAtEachEnd = 4;
  const std::size_t length = chain.size() - 1 - first;
  std::string text;
  for (std::size_t k = first; k + 1 < chain.size(); ++k) {
    const std::size_t at = k - first;
    if (length > 2 * kShownAtEachEnd && at == kShownAtEachEnd)
      text += "… (" + std::to_string(length - 2 * kShownAtEachEnd) + " more) -> ";
    if (length > 2 * kShownAtEachEnd && at >= kShownAtEachEnd && at < length - kShownAtEachEnd) continue;
    text += chain[k] + " -> ";
  }
  throw InputError(entries_.at(name).locate(0), "definition '" + name + "' depends on itself (" + text + name + ")");
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
