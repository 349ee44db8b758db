// CSV measurement and plan files: a header row, then one row per sample.
// Accepts a UTF-8 byte-order mark, CRLF line ends, blank lines, `#` comment
// lines and double-quoted fields. Every error names file:line:column.
#pragma once

#include <string>
#include <vector>

namespace massid {

struct CsvTable {
  std::string source;                           // file name, for messages
  std::vector<std::string> header;              // column names
  int header_line = 0;                          // file line of the header
  std::vector<std::vector<std::string>> rows;   // [num_rows][num_columns] raw cells
  std::vector<int> line;                        // [num_rows] file line of each row
  std::vector<std::vector<int>> column_offset;  // [num_rows][num_columns] 1-based char column

  int num_rows() const { return static_cast<int>(rows.size()); }
  int num_columns() const { return static_cast<int>(header.size()); }
  int find(const std::string& name) const;  // column index, -1 when absent
  // The cell as a finite number; throws InputError naming file:line:column.
  double number(int row, int column) const;
};

CsvTable read_csv(const std::string& path);
CsvTable parse_csv(const std::string& text, const std::string& source);

// Shortest text that reads back to the same double.
std::string format_number(double value);
// Writes header and rows as CSV through write_file_atomically.
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows);

}  // namespace massid
