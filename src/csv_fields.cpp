#include "csv_fields.hpp"

#include <fmt/format.h>

#include "massid/errors.hpp"

namespace massid::detail {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
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

}  // namespace massid::detail
