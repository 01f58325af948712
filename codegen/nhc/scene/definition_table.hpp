#pragma once
/// \file definition_table.hpp
/// \brief A scene's [definitions]: named values (scalars, vectors, matrices) written in any
/// order, resolved on first use, so that a definition may use others defined below it.
///
/// Each definition is parsed once, with the same rules as the Lagrangian, and substituted where
/// its name appears (expanded symbolically: the derivation sees coordinates only). A cycle is an
/// InputError at the definition that closes it; errors inside a definition point into its own
/// text. Usage is recorded so that a definition that nothing uses can be reported.

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/scene/expression_parser.hpp"

namespace nhc {

class DefinitionTable {
 public:
  /// Where an offset of a definition's text is in the scene file.
  using Locator = std::function<SourceLocation(std::size_t offset)>;

  /// `keep`: each definition's value is a named intermediate (SceneOptions::keep_definitions).
  DefinitionTable(const JetSpace& jet, ExpressionRules rules, bool keep = false)
      : jet_(jet), rules_(std::move(rules)), keep_(keep) {}

  void add(const std::string& name, std::string text, Locator locate);
  /// Rules for an expression that may use the definitions (the table must outlive them).
  ExpressionRules rules_with_definitions(ExpressionRules rules);
  /// The value of `name`, or nullopt when it is not a definition.
  std::optional<Value> resolve(const std::string& name);
  /// Resolves every definition not resolved yet (so that errors in unused ones are reported).
  void resolve_all();
  /// Definitions that no expression outside the table reaches, with their locations.
  std::vector<std::pair<std::string, SourceLocation>> unused() const;

 private:
  struct Entry {
    std::string text;
    Locator locate;
    std::optional<Value> value;
    bool in_progress = false;
    std::set<std::string> uses;  ///< definitions its text names
  };
  /// The definitions `text` names, each once, in order of appearance.
  std::vector<std::string> named_definitions(const std::string& text) const;
  /// Resolves what `root` uses, and what they use, leaves first with an explicit stack: parsing
  /// `root` then finds its definitions resolved, so a chain d_k = "d_{k-1}" of any length
  /// recurses one level, not one per link (the stack overflowed at about 2,400 links).
  void resolve_dependencies_first(const std::string& root);
  /// The InputError for a cycle: `chain` ends with the definition that closes it.
  [[noreturn]] void cycle(const std::vector<std::string>& chain) const;

  /// The value of definition `name` with each entry that is large when substituted
  /// (kSubstituteDefinitionBelowNodes) made a named intermediate (`v` for a scalar, `v_1`… for a
  /// vector, `M_12`… for a matrix); smaller entries are substituted.
  static Value named(const std::string& name, Value value);

  const JetSpace& jet_;
  ExpressionRules rules_;
  bool keep_ = false;
  std::map<std::string, Entry> entries_;
  std::vector<std::string> resolving_;  ///< the chain being resolved, for cycles and usage
  std::set<std::string> used_from_outside_;
};

}  // namespace nhc
