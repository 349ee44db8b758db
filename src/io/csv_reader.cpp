#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/csv_fields.hpp"
#include "io/csv_stream.hpp"
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
  detail::SampleColumns h;  // the header: the streaming reader's rules and messages
  detail::read_header(text, source, h);
  table.header = std::move(h.header);
  table.header_line = h.header_line;
  std::vector<std::string> fields;
  std::vector<int> offsets;
  std::string_view line;
  int line_no = h.header_line;
  for (size_t pos = h.data_begin; pos < text.size();) {
    pos = detail::next_line(text, pos, line);
    ++line_no;
    const std::string_view content = detail::trim(line);
    if (content.empty() || content.front() == '#') continue;
    detail::split(line, source, line_no, fields, offsets);
    detail::check_row_width(line, offsets, table.header.size(), source, line_no);
    table.rows.push_back(fields);
    table.column_offset.push_back(offsets);
    table.line.push_back(line_no);
  }
  if (table.rows.empty())
    throw InputError(fmt::format("{}:{}:1: header but no data rows", source, table.header_line));
  return table;
}

CsvTable read_csv(const std::string& path) { return parse_csv(read_file(path), path); }

}  // namespace massid
