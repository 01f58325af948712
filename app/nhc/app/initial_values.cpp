#include "nhc/app/initial_values.hpp"

#include <cmath>
#include <map>

#include "nhc/errors.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene_text.hpp"

namespace nhc::app {

namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& message) {
  throw InputError({field, 0, 0}, message);
}

/// "x=abc: " before a message about the value written `written`; nothing when the field alone names it.
std::string quoted(const std::string& written) { return written.empty() ? std::string() : written + ": "; }

bool names_coordinate_or_multiplier(const Scene& scene, const std::string& base) {
  const JetSpace& jet = *scene.jet;
  if (jet.coordinate_index(base)) return true;
  for (int a = 0; a < jet.multiplier_count(); ++a)
    if (jet.multiplier_name(a) == base) return true;
  return false;
}

}  // namespace

void apply_initial_values(Scene& scene, const std::vector<InitialValue>& values, const std::string& field) {
  // Which orders of each name the new values give; checked for gaps once all are in.
  std::map<std::string, std::string> written_by_name;
  for (const InitialValue& v : values) {
    if (!std::isfinite(v.value))
      refuse(field, quoted(v.written) + base::number_text(v.value, 17) + " is not a finite number");
    if (v.name == "t0") {
      scene.initial.t0 = v.value;
      scene.initial.t0_expression = {};  // a number now: --set no longer re-evaluates it
      // Without [simulate] t_end the run lasts 1 from t0 (scene_loader.cpp): from this t0.
      if (!scene.source_text().empty() && !scene_gives_t_end(scene.source_text())) scene.simulate.t_end = v.value + 1.0;
      continue;
    }
    const std::size_t primes = v.name.size() - std::min(v.name.size(), v.name.find_last_not_of('\'') + 1);
    const std::string base = v.name.substr(0, v.name.size() - primes);
    if (!names_coordinate_or_multiplier(scene, base)) {
      std::string known;
      for (const std::string& c : scene.jet->coordinates()) known += (known.empty() ? "" : ", ") + c;
      refuse(field, quoted(v.written) + "'" + base +
                        "' is neither t0, a coordinate nor a multiplier of the scene (coordinates: " + known + ")");
    }
    if (primes > static_cast<std::size_t>(kMaxDerivativeOrder))
      refuse(field, quoted(v.written) + "derivative order " + std::to_string(primes) + " is beyond the limit " +
                        std::to_string(kMaxDerivativeOrder));
    std::vector<double>& list = scene.initial.values[base];
    if (list.size() <= primes) list.resize(primes + 1, std::nan(""));  // NaN: not given (checked below)
    list[primes] = v.value;
    if (auto e = scene.initial.expressions.find(base);
        e != scene.initial.expressions.end() && primes < e->second.size())
      e->second[primes].clear();  // a number now: --set no longer re-evaluates it
    written_by_name[base] = v.written;
  }
  for (const auto& [base, written] : written_by_name)
    for (std::size_t k = 0; k < scene.initial.values[base].size(); ++k)
      if (std::isnan(scene.initial.values[base][k]))
        refuse(field, quoted(written) + base::primed_name(base, static_cast<int>(k)) +
                          " is not given (neither in the scene's [initial] nor here); the values of " + base +
                          " are a value and its derivatives in order, so give it too");
}

runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model) {
  return runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
}

}  // namespace nhc::app
