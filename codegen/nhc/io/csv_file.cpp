#include "nhc/io/csv_file.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/input_file.hpp"
#include "nhc/io/printable.hpp"

namespace nhc {

namespace {

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

}  // namespace

int csv_cell_column(const std::string& line, std::size_t index) {
  std::size_t at = 0;
  for (std::size_t k = 0; k < index; ++k) at = line.find(',', at) + 1;
  return static_cast<int>(at) + 1;
}

CsvFile read_csv_file(const std::string& path, const std::string& what) {
  const std::string text = read_input_file(path, what);
  CsvFile file;
  file.path = path;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF
    if (!have_header) {
      if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark (spreadsheets write one)
      for (const std::string& cell : split_commas(line)) file.header.push_back(trimmed(cell));
      file.header_text = line;
      have_header = true;
      continue;
    }
    if (trimmed(line).empty()) continue;
    CsvFile::Row row;
    row.line = number;
    row.text = line;
    for (const std::string& cell : split_commas(line)) row.cells.push_back(trimmed(cell));
    file.rows.push_back(std::move(row));
  }
  if (!have_header || (file.header.size() == 1 && file.header.front().empty()))
    throw InputError({path, 1, 1}, "empty file: a header row naming the columns is needed");
  return file;
}

int CsvFile::column(const std::string& name) const {
  int found = -1;
  for (std::size_t c = 0; c < header.size(); ++c) {
    if (header[c] != name) continue;
    if (found >= 0)
      throw InputError({path, 1, csv_cell_column(header_text, c)},
                       "duplicate column '" + printable(name) + "' (also column " + std::to_string(found + 1) + ")");
    found = static_cast<int>(c);
  }
  return found;
}

double CsvFile::number(std::size_t r, std::size_t c, bool finite_only) const {
  const Row& row = rows[r];
  const SourceLocation where{
      path, row.line, c < row.cells.size() ? csv_cell_column(row.text, c) : static_cast<int>(row.text.size()) + 1};
  const std::string name = c < header.size() ? printable(header[c]) : std::to_string(c + 1);
  if (c >= row.cells.size()) throw InputError(where, "missing value of column '" + name + "'");
  const std::string& text = row.cells[c];
  double v = 0;
  // from_chars reads no leading '+'; "+1" is a number all the same.
  const char* begin = text.data() + (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+');
  const auto [end, error] = std::from_chars(begin, text.data() + text.size(), v);
  if (error != std::errc() || end != text.data() + text.size() || text.empty())
    throw InputError(where, "'" + printable(text) + "' is not a " + (finite_only ? "finite " : "") + "number");
  if (finite_only && !std::isfinite(v)) throw InputError(where, "'" + printable(text) + "' is not a finite number");
  return v;
}

std::vector<std::vector<double>> CsvFile::numbers(bool finite_only) const {
  std::vector<std::vector<double>> out;
  out.reserve(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].cells.size() != header.size())
      throw InputError({path, rows[r].line, 1}, std::to_string(rows[r].cells.size()) + " cells, the header has " +
                                                    std::to_string(header.size()));
    std::vector<double> row;
    for (std::size_t c = 0; c < header.size(); ++c) row.push_back(number(r, c, finite_only));
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace nhc
