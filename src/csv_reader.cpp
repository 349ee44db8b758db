#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "massid/csv.hpp"
#include "massid/errors.hpp"

namespace massid {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// Splits one line into fields; offsets are 1-based character columns.
void split(std::string_view line, const std::string& source, int line_no,
           std::vector<std::string>& fields, std::vector<int>& offsets) {
  fields.clear();
  offsets.clear();
  size_t i = 0;
  while (true) {
    size_t start = i;
    while (start < line.size() && (line[start] == ' ' || line[start] == '\t')) ++start;
    std::string field;
    size_t end;
    if (start < line.size() && line[start] == '"') {
      size_t k = start + 1;
      bool closed = false;
      while (k < line.size()) {
        if (line[k] == '"') {
          if (k + 1 < line.size() && line[k + 1] == '"') {
            field += '"';
            k += 2;
            continue;
          }
          closed = true;
          ++k;
          break;
        }
        field += line[k++];
      }
      if (!closed)
        throw InputError(
            fmt::format("{}:{}:{}: unterminated quoted field", source, line_no, start + 1));
      end = line.find(',', k);
      if (!trim(line.substr(k, end == std::string_view::npos ? end : end - k)).empty())
        throw InputError(
            fmt::format("{}:{}:{}: text after a quoted field", source, line_no, k + 1));
    } else {
      end = line.find(',', i);
      field = std::string(trim(line.substr(i, end == std::string_view::npos ? end : end - i)));
    }
    fields.push_back(std::move(field));
    offsets.push_back(static_cast<int>(start + 1));
    if (end == std::string_view::npos) break;
    i = end + 1;
  }
}

}  // namespace

int CsvTable::find(const std::string& name) const {
  for (int i = 0; i < num_columns(); ++i)
    if (header[i] == name) return i;
  return -1;
}

double CsvTable::number(int row, int column) const {
  const std::string& cell = rows[row][column];
  double value = 0.0;
  const char* first = cell.data();
  const char* last = first + cell.size();
  if (!cell.empty() && *first == '+') ++first;
  auto result = fast_float::from_chars(first, last, value);
  auto where = [&] {
    return fmt::format("{}:{}:{}: column '{}'", source, line[row], column_offset[row][column],
                       header[column]);
  };
  if (cell.empty()) throw InputError(where() + ": empty cell, a number is expected");
  if (result.ec != std::errc() || result.ptr != last)
    throw InputError(fmt::format("{}: '{}' is not a number", where(), cell));
  if (!std::isfinite(value))
    throw InputError(fmt::format("{}: '{}' is not a finite number", where(), cell));
  return value;
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
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    split(line, source, line_no, fields, offsets);
    if (table.header.empty()) {
      table.header_line = line_no;
      for (size_t c = 0; c < fields.size(); ++c) {
        if (fields[c].empty())
          throw InputError(fmt::format("{}:{}:{}: empty column name in the header", source, line_no,
                                       offsets[c]));
        for (size_t d = 0; d < c; ++d)
          if (fields[d] == fields[c])
            throw InputError(fmt::format("{}:{}:{}: column '{}' appears twice in the header",
                                         source, line_no, offsets[c], fields[c]));
      }
      table.header = fields;
      continue;
    }
    if (fields.size() != table.header.size())
      throw InputError(fmt::format(
          "{}:{}:{}: row has {} fields, the header has {}", source, line_no,
          fields.size() < table.header.size() ? line.size() + 1 : offsets[table.header.size()],
          fields.size(), table.header.size()));
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
