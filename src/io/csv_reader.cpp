#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "io/csv_fields.hpp"
#include "massid/core/errors.hpp"
#include "massid/io/csv.hpp"

namespace massid {

int CsvTable::find(const std::string& name) const {
  for (int i = 0; i < num_columns(); ++i)
    if (header[i] == name) return i;
  return -1;
}

double CsvTable::number(int row, int column) const {
  return detail::cell_number(rows[row][column], source, line[row], column_offset[row][column],
                             header[column]);
}

CsvTable parse_csv(const std::string& text, const std::string& source) {
  CsvTable table;
  table.source = source;
  std::string_view rest(text);
  if (rest.substr(0, 3) == "\xEF\xBB\xBF") rest.remove_prefix(3);  // UTF-8 BOM
  int line_no = 0;
  std::vector<std::string> fields;
  std::vector<int> offsets;
  while (!rest.empty()) {
    const size_t nl = rest.find('\n');
    std::string_view line = rest.substr(0, nl);
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = detail::trim(line);
    if (content.empty() || content.front() == '#') continue;
    detail::split(line, source, line_no, fields, offsets);
    if (table.header.empty()) {
      table.header_line = line_no;
      detail::check_header(fields, offsets, source, line_no);
      table.header = fields;
      continue;
    }
    detail::check_row_width(line, offsets, table.header.size(), source, line_no);
    table.rows.push_back(fields);
    table.column_offset.push_back(offsets);
    table.line.push_back(line_no);
  }
  if (table.header.empty())
    throw InputError(fmt::format("{}:1:1: empty file, no header row", source));
  if (table.rows.empty())
    throw InputError(fmt::format("{}:{}:1: header but no data rows", source, table.header_line));
  return table;
}

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_csv(text.str(), path);
}

}  // namespace massid
