#include "nhc/app/output_selection.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/runtime/trajectory.hpp"

namespace nhc::app {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.push_back("");
  return parts;
}

[[noreturn]] void bad(const std::string& flag, const std::string& spec, const std::string& why) {
  throw InputError({flag, 0, 0}, flag + " " + spec + ": " + why);
}

}  // namespace

std::vector<double> parse_output_times(const std::string& spec) {
  const std::string flag = "--output-times";
  std::vector<double> times;
  if (spec.find(':') != std::string::npos) {
    const std::vector<std::string> parts = split(spec, ':');
    if (parts.size() != 3) bad(flag, spec, "expected START:STEP:END or a list T1,T2,…");
    const double a = parse_number(flag, parts[0]), h = parse_number(flag, parts[1]), b = parse_number(flag, parts[2]);
    if (!(h > 0)) bad(flag, spec, "the step must be positive");
    if (!(b > a)) bad(flag, spec, "the end must be after the start");
    const double steps = (b - a) / h;
    const double n = std::round(steps);
    if (std::abs(steps - n) > 1e-9 * std::max(1.0, n)) bad(flag, spec, "(END − START)/STEP is not a whole number");
    if (n > 1e7) bad(flag, spec, "more than 10^7 output times");
    for (long i = 0; i <= static_cast<long>(n); ++i)
      times.push_back(i == static_cast<long>(n) ? b : a + h * static_cast<double>(i));
  } else {
    for (const std::string& part : split(spec, ',')) times.push_back(parse_number(flag, part));
  }
  // Against t0 they are checked with the run's scene, its parameters set (check_run_request).
  check_output_time_order(times, flag, spec);
  return times;
}

std::vector<std::string> csv_columns(const runtime::Model& model, const std::vector<double>& p,
                                     const SceneOutputs& outputs, const ExtraColumns* extra) {
  std::ostringstream header;
  runtime::write_csv(header, model, p, {});
  std::string line = header.str();
  if (!line.empty() && line.back() == '\n') line.pop_back();
  std::vector<std::string> columns = split(line, ',');
  columns.insert(columns.end(), outputs.names().begin(), outputs.names().end());
  if (extra) columns.insert(columns.end(), extra->names.begin(), extra->names.end());
  return columns;
}

std::vector<std::string> parse_columns(const std::string& spec, const std::vector<std::string>& available) {
  std::vector<std::string> columns;
  for (const std::string& name : split(spec, ',')) {
    if (std::find(columns.begin(), columns.end(), name) != columns.end())
      bad("--columns", spec, "column '" + name + "' is named twice");
    if (name == "t") {  // always the first column; named alone, the only one
      columns.push_back(name);
      continue;
    }
    if (std::find(available.begin(), available.end(), name) == available.end()) {
      std::string known;
      for (const std::string& a : available) known += (known.empty() ? "" : ", ") + a;
      bad("--columns", spec, "no column '" + name + "' (columns: " + known + ")");
    }
    columns.push_back(name);
  }
  return columns;
}

void write_selected_csv(std::ostream& out, const runtime::Model& model, const std::vector<double>& p,
                        const std::vector<runtime::Sample>& samples, const std::vector<std::string>& columns,
                        const SceneOutputs& outputs, const ExtraColumns* extra) {
  if (columns.empty() && outputs.empty() && !extra) {
    runtime::write_csv(out, model, p, samples);
    return;
  }
  // The model's columns as numbers (runtime::CsvRows, what write_csv prints), the outputs' and
  // the extra columns appended as numbers, every field printed once by shortest_text: no column
  // goes through text and back, none is printed at another precision.
  std::vector<std::string> header = runtime::csv_header(model);
  header.insert(header.end(), outputs.names().begin(), outputs.names().end());
  if (extra) header.insert(header.end(), extra->names.begin(), extra->names.end());
  std::vector<std::size_t> keep;
  if (columns.empty())
    for (std::size_t k = 0; k < header.size(); ++k) keep.push_back(k);
  else keep.push_back(0);
  for (const std::string& c : columns)
    if (c != "t") keep.push_back(static_cast<std::size_t>(std::find(header.begin(), header.end(), c) - header.begin()));
  for (std::size_t k = 0; k < keep.size(); ++k) out << (k ? "," : "") << header.at(keep[k]);
  out << "\n";
  const runtime::CsvRows rows(model, p);
  std::vector<double> values;
  std::string line;
  for (std::size_t row = 0; row < samples.size(); ++row) {
    rows.row(samples[row], values);
    if (!outputs.empty()) {
      const std::vector<double> more = outputs.evaluate(samples[row]);
      values.insert(values.end(), more.begin(), more.end());
    }
    if (extra) values.insert(values.end(), extra->rows.at(row).begin(), extra->rows.at(row).end());
    line.clear();
    for (std::size_t k : keep) base::append_shortest(line, ',', values.at(k));
    line.erase(0, 1);  // the first column has no comma
    line += '\n';
    out << line;
  }
}

}  // namespace nhc::app
