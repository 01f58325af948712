#pragma once
// Reading the CSV files nhc writes, in tests: a trajectory's columns by name and an event table.

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace nhc::test {

/// The columns of a CSV text by their header names (every cell a number).
std::map<std::string, std::vector<double>> csv_columns(const std::string& csv);

/// The rows (name, t) of an event table (`<stem>.events.csv`, header `name,t`); throws
/// std::runtime_error when the header or a row is not of that form.
std::vector<std::pair<std::string, double>> event_rows(const std::string& csv);

}  // namespace nhc::test
