#pragma once
/// \file csv_file.hpp
/// \brief The one CSV reader of data files (docs/safety.md, "Reading: limits"): `--input
/// NAME=@FILE.csv`, `nhc optimize --guess`, `nhc animate --path` and nhc's own tables read back.
/// A regular file of at most kInputSizeLimit bytes; a UTF-8 byte order mark dropped; CRLF line
/// ends read; blank lines skipped; cells trimmed. Every fault is an InputError at FILE:LINE:COLUMN
/// (the character column of the cell) with the cell's text escaped (printable.hpp).

#include <string>
#include <vector>

namespace nhc {

struct CsvFile {
  std::string path;
  std::vector<std::string> header;  ///< the first line's names, trimmed
  std::string header_text;          ///< the first line (without a byte order mark)
  struct Row {
    int line = 0;                    ///< 1-based line in the file
    std::string text;                ///< the line without its line end
    std::vector<std::string> cells;  ///< trimmed
  };
  std::vector<Row> rows;

  /// The column named `name`: -1 when none; InputError at the header for a duplicate.
  int column(const std::string& name) const;
  /// The number in row `row`, column `column`: InputError at its place when the cell is missing
  /// or not a number; `finite_only` also refuses nan and ±inf (written "nan", "inf").
  double number(std::size_t row, std::size_t column, bool finite_only = true) const;
  /// Every row as numbers, each as wide as the header: InputError at the first row of another
  /// width or the first cell that is not a (finite, with `finite_only`) number.
  std::vector<std::vector<double>> numbers(bool finite_only = true) const;
};

/// Reads `path` under the rules above; `what` names it in a refusal ("a CSV file for --guess").
/// InputError for a file that is not a regular one, too large, unreadable or without a header.
CsvFile read_csv_file(const std::string& path, const std::string& what);

/// Column (1-based, in characters) where cell `index` of `line` starts.
int csv_cell_column(const std::string& line, std::size_t index);

}  // namespace nhc
