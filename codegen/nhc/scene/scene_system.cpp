// SceneSystem::source_text(): the text stands for the system only while every field is what it
// was read as (docs/architecture.md, "The scene's three parts").
#include <sstream>
#include <utility>

#include "nhc/scene/scene.hpp"

namespace nhc {

namespace {

/// The fields of a system as something to compare: the expressions themselves (held, so that
/// none is freed and its address reused while the record lives), the jet space, and every other
/// value written out.
struct Fields {
  std::vector<GiNaC::ex> expressions;
  std::shared_ptr<const JetSpace> jet;
  std::string values;
};

/// Walks every field of a system: records them (`recorded` null), or compares them with a record
/// without copying an expression (no reference count is touched: the check only reads).
class SystemWalk {
 public:
  explicit SystemWalk(const Fields* recorded = nullptr) : recorded_(recorded) {}
  Fields fields;
  bool differs = false;  ///< an expression or the jet space differs from the record

  void add(const GiNaC::ex& e) {
    if (!recorded_) {
      fields.expressions.push_back(e);
    } else if (count_ >= recorded_->expressions.size()) {
      differs = true;
    } else {
      // The same tree, or an equal one (GiNaC may make equal trees share one).
      const GiNaC::ex& then = recorded_->expressions[count_];
      if (!GiNaC::are_ex_trivially_equal(e, then) && !e.is_equal(then)) differs = true;
    }
    ++count_;
  }
  void add(const std::string& s) { out_ << s.size() << ':' << s << ';'; }
  void add(bool b) { out_ << (b ? 'y' : 'n') << ';'; }
  void add(int i) { out_ << i << ';'; }
  void add(ModelKind kind) { add(static_cast<int>(kind)); }
  void add(const SourceLocation& at) {
    const auto& [file, line, column] = at;
    add(file), add(line), add(column);
  }
  void add(const DerivedParameter& d) {
    const auto& [name, value] = d;
    add(name), add(value);
  }
  void add(const SceneInput& u) {
    const auto& [name, default_signal, where, law, feedback] = u;
    add(name), add(default_signal), add(where), add(law), add(feedback);
  }
  void add(const SceneQuantity& q) {
    const auto& [name, expression, where, required] = q;
    add(name), add(expression), add(where), add(required);
  }
  template <typename A, typename B>
  void add(const std::pair<A, B>& p) {
    add(p.first), add(p.second);
  }
  template <typename K, typename V>
  void add(const std::map<K, V>& m) {
    add(static_cast<int>(m.size()));
    for (const auto& entry : m) add(entry.first), add(entry.second);
  }
  template <typename T>
  void add(const std::vector<T>& v) {
    add(static_cast<int>(v.size()));
    for (const T& x : v) add(x);
  }
  void add(const EulerChain& c) {
    const auto& [axes, angles, determinant, zeros] = c;
    add(axes), add(angles), add(determinant), add(zeros);
  }
  void add(const SceneReference& r) {
    const auto& [all, per_model] = r;
    add(all), add(per_model);
  }

  /// Every field of the system: a field added to SceneSystemFields stops this from compiling
  /// until it is listed here (the structured bindings name them all), so none is left unchecked.
  void add(const SceneSystemFields& system) {
    const auto& [name, source_path, keep_definitions, jet, derived_parameters, lagrangian, lagrangian_where,
                 constraints, constraint_texts, dependent, models, models_where, constraints_where, forces, inputs,
                 invariants, reference, euler_chains] = system;
    add(name), add(source_path), add(keep_definitions);
    if (!recorded_) fields.jet = jet;
    else if (recorded_->jet != jet) differs = true;
    add(derived_parameters), add(lagrangian), add(lagrangian_where), add(constraints), add(constraint_texts);
    add(dependent), add(models), add(models_where), add(constraints_where), add(forces), add(inputs), add(invariants),
        add(reference), add(euler_chains);
    fields.values = out_.str();
    if (recorded_ && (count_ != recorded_->expressions.size() || fields.values != recorded_->values)) differs = true;
  }

 private:
  const Fields* recorded_;
  std::size_t count_ = 0;
  std::ostringstream out_;
};

Fields fields_of(const SceneSystemFields& system) {
  SystemWalk writer;
  writer.add(system);
  return std::move(writer.fields);
}

bool same(const SceneSystemFields& system, const Fields& recorded) {
  SystemWalk writer(&recorded);
  writer.add(system);
  return !writer.differs;
}

}  // namespace

struct SceneSystem::Reading {
  std::string text;
  Fields fields;
};

const std::string& SceneSystem::source_text() const {
  static const std::string none;
  if (!reading_ || !same(*this, reading_->fields)) return none;
  return reading_->text;
}

void SceneSystem::set_source_text(std::string text) {
  reading_ = std::make_shared<const Reading>(Reading{std::move(text), fields_of(*this)});
}

}  // namespace nhc
