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
#include "nhc/io/csv_file.hpp"
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

Series read_series(const std::string& path, const std::string& name, double t0, double t_end) {
  // The one CSV reader of data files (nhc/io/csv_file.hpp): regular file, size limit, CRLF, a
  // byte order mark, escaped messages at the cell's line and column.
  const CsvFile file = read_csv_file(path, "a CSV file for input '" + name + "'");
  const int t_column = file.column("t"), u_column = file.column(name);
  if (t_column < 0) throw InputError({path, 1, 1}, "no column 't' in the header row");
  if (u_column < 0) {
    std::string header;
    for (std::size_t c = 0; c < file.header.size(); ++c) header += (c ? "," : "") + file.header[c];
    throw InputError({path, 1, 1}, "no column '" + name + "' in the header row (" + printable(header) + ")");
  }
  Series s;
  for (std::size_t r = 0; r < file.rows.size(); ++r) {
    const double pair[2] = {file.number(r, static_cast<std::size_t>(t_column)),
                            file.number(r, static_cast<std::size_t>(u_column))};
    const int row = file.rows[r].line;
    const std::string& line = file.rows[r].text;
    if (!s.t.empty() && !(pair[0] > s.t.back())) {
      std::ostringstream message;
      message << "times must increase: t = " << pair[0] << " follows t = " << s.t.back();
      throw InputError({path, row, csv_cell_column(line, static_cast<std::size_t>(t_column))}, message.str());
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
    throw InputError(
        kFlag, "in " + name + "=" + text + " at character " + std::to_string(error.offset() + 1) + ": " + error.what());
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
                                  (known.empty() ? std::string("the scene has no [inputs]") : "inputs: " + known) +
                                  ")");
    }
    // A feedback law of the scene is compiled into the equations: a signal for it would drive nothing.
    if (scene.inputs[static_cast<std::size_t>(*k)].feedback)
      throw InputError(kFlag, "input '" + name +
                                  "' is a feedback law of the scene (compiled into its equations); "
                                  "change the law in [inputs]");
    Signal signal =
        !text.empty() && text[0] == '@'
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
