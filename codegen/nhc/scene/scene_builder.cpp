// SceneBuilder: writes the scene file a user would write, then reads it with the scene loader,
// so that scenes built in code and scenes read from disk share one validation.
#include "nhc/scene/scene_builder.hpp"

#include "nhc/base/number_text.hpp"

#include <cstdio>
#include <sstream>

namespace nhc {

namespace {

/// A TOML basic string: quotes, backslashes and control characters escaped.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

/// 17 significant digits: the double reads back exactly. inf and nan are TOML too, and the
/// loader rejects them with its own message.
std::string number(double v) { return base::number_text(v, 17); }

std::string string_array(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + quoted(items[i]);
  return out + "]";
}

std::string number_array(const std::vector<double>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + number(items[i]);
  return out + "]";
}

}  // namespace

SceneBuilder::SceneBuilder(std::string name) : name_(std::move(name)) {}

SceneBuilder& SceneBuilder::coordinates(std::vector<std::string> names) {
  coordinates_ = std::move(names);
  return *this;
}
SceneBuilder& SceneBuilder::parameter(const std::string& name, double value) {
  parameters_.emplace_back(name, value);
  return *this;
}
SceneBuilder& SceneBuilder::lagrangian(std::string expression) {
  lagrangian_ = std::move(expression);
  return *this;
}
SceneBuilder& SceneBuilder::constraint(std::string expression) {
  constraints_.push_back(std::move(expression));
  return *this;
}
SceneBuilder& SceneBuilder::dependent(std::vector<std::string> coordinates) {
  dependent_ = std::move(coordinates);
  return *this;
}
SceneBuilder& SceneBuilder::models(std::vector<ModelKind> models) {
  models_ = std::move(models);
  return *this;
}
SceneBuilder& SceneBuilder::initial_time(double t0) {
  t0_ = t0;
  return *this;
}
SceneBuilder& SceneBuilder::initial(const std::string& variable, std::vector<double> values) {
  initial_.emplace_back(variable, std::move(values));
  return *this;
}
SceneBuilder& SceneBuilder::simulate(ModelKind model, double t_end, double rtol, double atol) {
  simulate_ = SimulateEntry{model, t_end, rtol, atol};
  return *this;
}
SceneBuilder& SceneBuilder::reference(const std::string& coordinate, std::string expression) {
  reference_.emplace_back(coordinate, std::move(expression));
  return *this;
}
SceneBuilder& SceneBuilder::invariant(const std::string& name, std::string expression) {
  invariants_.emplace_back(name, std::move(expression));
  return *this;
}

SceneBuilder& SceneBuilder::definition(const std::string& name, std::string expression) {
  definitions_.emplace_back(name, std::move(expression));
  return *this;
}
SceneBuilder& SceneBuilder::force(const std::string& coordinate, std::string expression) {
  forces_.emplace_back(coordinate, std::move(expression));
  return *this;
}

std::string SceneBuilder::toml() const {
  std::ostringstream out;
  out << "# scene " << quoted(name_) << ", built in code (nhc::SceneBuilder)\n";
  out << "name = " << quoted(name_) << "\n";
  out << "coordinates = " << string_array(coordinates_) << "\n";
  out << "lagrangian = " << quoted(lagrangian_) << "\n";
  if (!constraints_.empty()) out << "constraints = " << string_array(constraints_) << "\n";
  if (!dependent_.empty()) out << "dependent = " << string_array(dependent_) << "\n";
  if (!models_.empty()) {
    std::vector<std::string> names;
    for (ModelKind m : models_) names.push_back(to_string(m));
    out << "models = " << string_array(names) << "\n";
  }
  // Quoted keys throughout: a bad name reaches the loader, which explains what is wrong with it.
  if (!parameters_.empty()) {
    out << "\n[parameters]\n";
    for (const auto& [name, value] : parameters_) out << quoted(name) << " = " << number(value) << "\n";
  }
  if (t0_ || !initial_.empty()) {
    out << "\n[initial]\n";
    if (t0_) out << "t0 = " << number(*t0_) << "\n";
    for (const auto& [variable, values] : initial_) out << quoted(variable) << " = " << number_array(values) << "\n";
  }
  if (simulate_) {
    out << "\n[simulate]\n"
        << "model = " << quoted(to_string(simulate_->model)) << "\n"
        << "t_end = " << number(simulate_->t_end) << "\n"
        << "rtol = " << number(simulate_->rtol) << "\n"
        << "atol = " << number(simulate_->atol) << "\n";
  }
  if (!reference_.empty()) {
    out << "\n[reference]\n";
    for (const auto& [coordinate, expression] : reference_)
      out << quoted(coordinate) << " = " << quoted(expression) << "\n";
  }
  if (!invariants_.empty()) {
    out << "\n[invariants]\n";
    for (const auto& [name, expression] : invariants_) out << quoted(name) << " = " << quoted(expression) << "\n";
  }
  for (const auto& [title, entries] : {std::pair{"definitions", &definitions_}, std::pair{"forces", &forces_}}) {
    if (entries->empty()) continue;
    out << "\n[" << title << "]\n";
    for (const auto& [key, expression] : *entries) out << quoted(key) << " = " << quoted(expression) << "\n";
  }
  return out.str();
}

Scene SceneBuilder::build() const {
  const std::string text = toml();
  Scene scene = parse_scene(text, name_ + " (built in code)");
  scene.source_path.clear();
  scene.set_source_text(text);  // the text stands for the system without the path
  return scene;
}

}  // namespace nhc
