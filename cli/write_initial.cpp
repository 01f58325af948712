#include "write_initial.hpp"

#include "nhc/base/number_text.hpp"

#include <map>
#include <ostream>
#include <sstream>

namespace nhc::cli {

namespace {

std::string number(double v) {
  // The shortest text that reads back as the same double, as in every data file nhc writes.
  std::string s = base::shortest_text(v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // a TOML float
  return s;
}

}  // namespace

void write_initial_table(std::ostream& out, const Scene& scene, const std::string& model,
                         const ConsistentPoint& point) {
  // Per unknown, its values x_j^(k), k < d_j, in order; named by the order-0 value.
  std::map<int, std::map<int, const InitialValue*>> by_unknown;
  for (const InitialValue& v : point.values) by_unknown[v.unknown][v.order] = &v;
  out << "# The consistent initial point of the " << model << " model of " << scene.name
      << " (nhc analyze --write-initial)\n[initial]\nt0 = " << number(point.t0) << "\n";
  for (const auto& [unknown, orders] : by_unknown) {
    const auto base = orders.find(0);
    if (base == orders.end()) continue;
    out << base->second->name << " = [";
    int k = 0;
    for (const auto& [order, value] : orders) {
      if (order != k++) break;  // only a leading run of orders is a [initial] list
      out << (order ? ", " : "") << number(value->value);
    }
    out << "]\n";
  }
  if (!scene.initial.fixed.empty()) {
    out << "fixed = [";
    for (std::size_t i = 0; i < scene.initial.fixed.size(); ++i)
      out << (i ? ", " : "") << '"' << scene.initial.fixed[i] << '"';
    out << "]\n";
  }
}

}  // namespace nhc::cli
