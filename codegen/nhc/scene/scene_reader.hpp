#pragma once
/// \file scene_reader.hpp
/// \brief What the parts of the scene reader (scene_loader.cpp and the readers of its tables)
/// share; not installed: the public face is load_scene() and parse_scene() (scene.hpp).

#include "nhc/scene/scene_toml.hpp"

#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "nhc/scene/definition_table.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/value.hpp"

namespace nhc::scene_reading {

/// Non-printable bytes are shown as \xNN so that the one-line message stays one line; a
/// long text is cut after 60 bytes (at a character boundary) and marked with "...".
std::string printable(const std::string& text);

bool is_function_name(const std::string& name);
/// lambda<N>: a multiplier's name.
bool looks_like_multiplier(const std::string& name);
/// name_d<N>: a jet variable's name.
bool has_jet_suffix(const std::string& name);

/// Reads a scene file's text into a Scene: read() checks the text, parses it and reads the tables
/// by part; each group of member functions below is defined in the file its comment names.
class SceneReader {
 public:
  SceneReader(const std::string& text, std::string path, SceneOptions options)
      : text_(text), path_(std::move(path)), options_(options) {
    std::istringstream lines(text_);
    for (std::string line; std::getline(lines, line);) lines_.push_back(line);
  }

  Scene read();  // scene_loader.cpp

 private:
  // scene_reader.cpp: what every part uses
  SourceLocation at(const toml::node& node) const { return at(node.source()); }
  SourceLocation at(const toml::source_region& region) const;
  [[noreturn]] void fail(const toml::node& node, const std::string& message) const;
  static std::string shortest(double v);
  void check_keys(const toml::table& table, const std::set<std::string>& allowed) const;
  const toml::node& require(const toml::table& table, const std::string& key, const std::string& where) const;
  std::string string_value(const toml::node& node, const std::string& what) const;
  const toml::array& array_value(const toml::node& node, const std::string& what) const;
  const toml::table& table_value(const toml::node& node, const std::string& what) const;
  double number_value(const toml::node& node, const std::string& what) const;
  NumberExpression number_expression(const toml::node& node) const;
  static std::string type_name(const toml::node& node);
  void check_variable_name(const toml::node& node, const std::string& n, const std::string& what);
  void check_variable_name_at(const SourceLocation& where, const std::string& n, const std::string& what);
  SourceLocation expression_location(const toml::node& node, std::size_t offset) const;
  GiNaC::ex expression(const toml::node& node, const std::string& what, const JetSpace& jet,
                       const ExpressionRules& rules) const;
  bool is_zero_at(const toml::node& node, const GiNaC::ex& e) const;
  static ExpressionRules multipliers_allowed(ExpressionRules rules);
  std::vector<std::pair<const toml::key*, const toml::node*>> entries_in_file_order(const toml::node& node,
                                                                                    const std::string& table) const;
  std::vector<SceneQuantity> read_quantities(const toml::node& node, const std::string& table, const std::string& what,
                                             const JetSpace& jet, const ExpressionRules& rules);
  double constant_value(const toml::node& node, const std::string& what) const;

  // scene_system_reader.cpp: the system
  void read_definitions(const toml::table& root, DefinitionTable& definitions);
  void read_reference(const toml::node& node, Scene& scene, const ExpressionRules& mechanics);
  void read_input_signals(const std::vector<std::pair<const toml::node*, SourceLocation>>& nodes, Scene& scene,
                          const ExpressionRules& rules);
  void read_forces(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  template <class Names>
  static std::vector<std::string> names_among(const std::string& text, const Names& names);
  static bool names_any_of(const std::string& text, const std::set<std::string>& names);
  std::optional<Value> derived_parameter(const std::string& name, const JetSpace& jet);
  void read_derived_parameters(Scene& scene);

  // scene_experiment_reader.cpp: the experiment
  void read_events(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  void read_contacts(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  void read_controller(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  void read_mpc(const toml::node& node, const toml::table& controller, Scene& scene);
  static GiNaC::exmap initial_point_of(const Scene& scene);
  void read_initial(const toml::table& root, Scene& scene);
  void check_fixed(Scene& scene);
  void read_simulate(const toml::table& root, Scene& scene);

  // scene_presentation_reader.cpp: the presentation
  void read_outputs(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  Value value_at(const toml::node& node, const std::string& what, const JetSpace& jet, const ExpressionRules& rules);
  void read_visuals(const toml::table& root, Scene& scene, const ExpressionRules& rules);
  void check_visual_value(const toml::node& node, const std::string& what, VisualValueKind kind, const Value& v,
                          const ExpressionRules& rules) const;
  std::string color_value(const toml::node& node, const std::string& what) const;

  const std::string& text_;
  std::string path_;
  SceneOptions options_;
  std::map<std::string, double> constants_;                 ///< the parameters, once read
  std::map<std::string, const toml::node*> derived_nodes_;  ///< [parameters] computed from others
  std::map<std::string, GiNaC::ex> derived_values_;         ///< … as expressions of the parameters
  std::vector<std::string> derived_order_;                  ///< … each after those it uses
  std::vector<std::string> derived_chain_;                  ///< being resolved (for cycles)
  std::vector<const toml::node*> fixed_nodes_;              ///< [initial] fixed, checked after the values
  std::vector<std::string> lines_;
  std::set<std::string> names_;
};

/// [optimize] of the scene file's table `root` into scene.optimize, once the rest of the scene is
/// read (its names, parameters, [simulate] and [outputs]); its expressions by `rules`, the
/// Lagrangian's (the [definitions] and the parameters computed from others resolved). Every
/// problem is an InputError at its FILE:LINE:COLUMN of `path`.
void read_optimize(const toml::table& root, Scene& scene, const std::string& path, const ExpressionRules& rules);

}  // namespace nhc::scene_reading
