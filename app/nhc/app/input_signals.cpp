#include "nhc/app/input_signals.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include "nhc/expr/numeric_program.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/input_file.hpp"
#include "nhc/io/printable.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/app/parameter_overrides.hpp"

namespace nhc::app {

namespace {

const SourceLocation kFlag{"--input", 0, 0};
using Signal = InputSignals::Signal;

/// A time series read from CSV, linearly interpolated.
struct Series {
  std::vector<double> t, value;
  double at(double time) const {
    const auto upper = std::upper_bound(t.begin(), t.end(), time);
    if (upper == t.begin()) return value.front();
    if (upper == t.end()) return value.back();
    const auto k = static_cast<std::size_t>(upper - t.begin());
    const double w = (time - t[k - 1]) / (t[k] - t[k - 1]);
    return (1 - w) * value[k - 1] + w * value[k];
  }
};

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  std::size_t start = 0;
  while (start < s.size() && (s[start] == ' ' || s[start] == '\t')) ++start;
  return s.substr(start);
}

/// Column (1-based) where cell `index` of `line` starts.
int column_of(const std::string& line, std::size_t index) {
  std::size_t at = 0;
  for (std::size_t k = 0; k < index; ++k) at = line.find(',', at) + 1;
  return static_cast<int>(at) + 1;
}

Series read_series(const std::string& path, const std::string& name, double t0, double t_end) {
  check_input_file(path, "a CSV file for input '" + name + "'");
  std::ifstream in(path);
  if (!in) throw InputError(kFlag, "cannot read '" + path + "' for input '" + name + "'");
  std::string header;
  if (!std::getline(in, header)) throw InputError({path, 1, 1}, "empty file: a header row naming t and " + name + " is needed");
  if (header.rfind("\xEF\xBB\xBF", 0) == 0) header.erase(0, 3);  // a UTF-8 byte order mark (spreadsheets write one)
  const std::vector<std::string> names = split_commas(header);
  std::size_t t_column = names.size(), u_column = names.size();
  for (std::size_t c = 0; c < names.size(); ++c) {
    const std::string n = trimmed(names[c]);
    if (n != "t" && n != name) continue;
    std::size_t& column = n == "t" ? t_column : u_column;
    if (column != names.size())
      throw InputError({path, 1, column_of(header, c)},
                       "duplicate column '" + n + "' (also column " + std::to_string(column + 1) + ")");
    column = c;
  }
  if (t_column == names.size()) throw InputError({path, 1, 1}, "no column 't' in the header row");
  if (u_column == names.size()) throw InputError({path, 1, 1}, "no column '" + name + "' in the header row (" + printable(header) + ")");
  Series s;
  std::string line;
  for (int row = 2; std::getline(in, line); ++row) {
    if (trimmed(line).empty()) continue;
    const std::vector<std::string> cells = split_commas(line);
    double pair[2];
    const std::size_t columns[2] = {t_column, u_column};
    for (int k = 0; k < 2; ++k) {
      const std::size_t c = columns[k];
      const SourceLocation where{path, row, c < cells.size() ? column_of(line, c) : static_cast<int>(line.size()) + 1};
      if (c >= cells.size()) throw InputError(where, "missing value of column '" + printable(trimmed(names[c])) + "'");
      const std::string text = trimmed(cells[c]);
      // from_chars reads no leading '+'; "+1" is a number all the same.
      const char* begin = text.data() + (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+');
      const auto [end, error] = std::from_chars(begin, text.data() + text.size(), pair[k]);
      if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(pair[k]))
        throw InputError(where, "'" + printable(text) + "' is not a finite number");
    }
    if (!s.t.empty() && !(pair[0] > s.t.back())) {
      std::ostringstream message;
      message << "times must increase: t = " << pair[0] << " follows t = " << s.t.back();
      throw InputError({path, row, column_of(line, t_column)}, message.str());
    }
    s.t.push_back(pair[0]);
    s.value.push_back(pair[1]);
  }
  if (s.t.size() < 2) throw InputError({path, 1, 1}, "a time series needs at least two rows");
  if (s.t.front() > t0 || s.t.back() < t_end) {
    std::ostringstream message;
    message << "the series covers t from " << s.t.front() << " to " << s.t.back() << ", the run goes from " << t0
            << " to " << t_end;
    throw InputError({path, 2, 1}, message.str());
  }
  return s;
}

Signal expression_signal(const Scene& scene, const std::string& name, const std::string& text) {
  ExpressionRules rules;
  rules.allow_coordinates = false;  // t and the parameters
  GiNaC::ex e;
  try {
    e = parse_expression(text, *scene.jet, rules);
  } catch (const ExpressionSyntaxError& error) {
    throw InputError(kFlag, "in " + name + "=" + text + " at character " + std::to_string(error.offset() + 1) + ": " +
                                error.what());
  }
  std::vector<GiNaC::ex> symbols{scene.jet->time()};
  std::vector<double> values{0.0};
  for (int k = 0; k < static_cast<int>(scene.parameter_values.size()); ++k) {
    symbols.push_back(scene.jet->parameter(k));
    values.push_back(scene.parameter_values[static_cast<std::size_t>(k)]);
  }
  auto program = std::make_shared<NumericProgram>(symbols);
  program->add(e, "input " + name);
  return [program, values](double t) mutable {
    values[0] = t;
    try {
      return program->evaluate(values, "the input")[0];
    } catch (const MathError&) {
      return std::nan("");  // the residual is then not finite: the integrator reports t
    }
  };
}

}  // namespace

std::vector<std::string> input_files(const std::vector<std::string>& assignments) {
  std::vector<std::string> files;
  for (const std::string& assignment : assignments)
    if (const auto at = assignment.find("=@"); at != std::string::npos) files.push_back(assignment.substr(at + 2));
  return files;
}

InputSignals parse_input_signals(const Scene& scene, const std::vector<std::string>& assignments, double t0,
                                 double t_end) {
  InputSignals out;
  for (const std::string& assignment : assignments) {
    const auto [name, text] = split_assignment("--input", assignment);
    const std::optional<int> k = scene.jet->input_index(name);
    if (!k) {
      std::string known;
      for (const SceneInput& u : scene.inputs) known += (known.empty() ? "" : ", ") + u.name;
      throw InputError(kFlag, "unknown input '" + name + "' (" +
                                  (known.empty() ? std::string("the scene has no [inputs]") : "inputs: " + known) + ")");
    }
    // A feedback law of the scene is compiled into the equations: a signal for it would drive nothing.
    if (scene.inputs[static_cast<std::size_t>(*k)].feedback)
      throw InputError(kFlag, "input '" + name + "' is a feedback law of the scene (compiled into its equations); "
                              "change the law in [inputs]");
    Signal signal = !text.empty() && text[0] == '@'
                        ? Signal([series = read_series(text.substr(1), name, t0, t_end)](double t) { return series.at(t); })
                        : expression_signal(scene, name, text);
    auto& signals = out.signals;  // the last of repeated names wins, as for --set
    signals.erase(std::remove_if(signals.begin(), signals.end(), [&](const auto& s) { return s.first == *k; }),
                  signals.end());
    signals.emplace_back(*k, std::move(signal));
  }
  return out;
}

runtime::InputFunction input_function(const InputSignals& signals, const runtime::Model& model,
                                      const std::vector<double>& parameters) {
  if (signals.signals.empty()) return {};
  const nhc_model_table* table = &model.table();
  return [table, signals = signals.signals, parameters](double t, const double*, double* u) {
    table->default_inputs(t, parameters.data(), u);  // the inputs without --input
    for (const auto& [k, signal] : signals) u[k] = signal(t);
  };
}

}  // namespace nhc::app
