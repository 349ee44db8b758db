#include "io/csv_fields.hpp"

#include <fast_float/fast_float.h>
#include <fmt/format.h>

#include <cmath>

#include "massid/core/errors.hpp"

namespace massid::detail {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

size_t next_line(std::string_view text, size_t pos, std::string_view& line) {
  const size_t nl = text.find('\n', pos);
  const size_t end = nl == std::string_view::npos ? text.size() : nl;
  line = text.substr(pos, end - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return nl == std::string_view::npos ? text.size() : nl + 1;
}

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

void check_header(const std::vector<std::string>& fields, const std::vector<int>& offsets,
                  const std::string& source, int line_no) {
  for (size_t c = 0; c < fields.size(); ++c) {
    if (fields[c].empty())
      throw InputError(
          fmt::format("{}:{}:{}: empty column name in the header", source, line_no, offsets[c]));
    for (size_t d = 0; d < c; ++d)
      if (fields[d] == fields[c])
        throw InputError(fmt::format("{}:{}:{}: column '{}' appears twice in the header", source,
                                     line_no, offsets[c], fields[c]));
  }
}

void check_row_width(std::string_view line, const std::vector<int>& offsets, size_t header_size,
                     const std::string& source, int line_no) {
  if (offsets.size() != header_size)
    throw InputError(
        fmt::format("{}:{}:{}: row has {} fields, the header has {}", source, line_no,
                    offsets.size() < header_size ? line.size() + 1 : offsets[header_size],
                    offsets.size(), header_size));
}

double cell_number(std::string_view cell, const std::string& source, int line_no, int column,
                   const std::string& name) {
  double value = 0.0;
  const char* first = cell.data();
  const char* last = first + cell.size();
  if (!cell.empty() && *first == '+') ++first;
  auto result = fast_float::from_chars(first, last, value);
  auto where = [&] { return fmt::format("{}:{}:{}: column '{}'", source, line_no, column, name); };
  if (cell.empty()) throw InputError(where() + ": empty cell, a number is expected");
  if (result.ec != std::errc() || result.ptr != last)
    throw InputError(fmt::format("{}: '{}' is not a number", where(), cell));
  if (!std::isfinite(value))
    throw InputError(fmt::format("{}: '{}' is not a finite number", where(), cell));
  return value;
}

}  // namespace massid::detail
