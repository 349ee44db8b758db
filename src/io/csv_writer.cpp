#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "massid/io/csv.hpp"

namespace massid {
namespace {

void append_cell(std::string& out, const std::string& cell) {
  if (cell.find_first_of(",\"\n") == std::string::npos) {
    out += cell;
    return;
  }
  out += '"';
  for (char c : cell) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void append_row(std::string& out, const std::vector<std::string>& row) {
  for (size_t i = 0; i < row.size(); ++i) {
    if (i) out += ',';
    append_cell(out, row[i]);
  }
  out += '\n';
}

}  // namespace

std::string format_number(double value) { return fmt::format("{}", value); }

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<std::string>>& rows) {
  std::string out;
  append_row(out, header);
  for (const auto& row : rows) append_row(out, row);
  write_file_atomically(path, out);
}

}  // namespace massid
