#include "csv_table.hpp"

#include <sstream>
#include <stdexcept>

namespace nhc::test {

std::map<std::string, std::vector<double>> csv_columns(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, cell;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::istringstream header(line); std::getline(header, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> out;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    for (std::size_t k = 0; k < names.size() && std::getline(row, cell, ','); ++k)
      out[names[k]].push_back(std::stod(cell));
  }
  return out;
}

std::vector<std::pair<std::string, double>> event_rows(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  if (line != "name,t") throw std::runtime_error("an event table starts with `name,t`, not `" + line + "`");
  std::vector<std::pair<std::string, double>> rows;
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    if (comma == std::string::npos) throw std::runtime_error("an event row without a comma: `" + line + "`");
    rows.emplace_back(line.substr(0, comma), std::stod(line.substr(comma + 1)));
  }
  return rows;
}

}  // namespace nhc::test
