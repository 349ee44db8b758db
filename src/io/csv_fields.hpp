// One CSV line into fields, a header's names, a cell into a number: the rules
// and messages that the whole-file reader (csv_reader.cpp) and the streaming
// reader (csv_stream.cpp) share.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace massid::detail {

// s without leading blanks and trailing blanks or '\r'.
std::string_view trim(std::string_view s);

// The line starting at byte pos of text (without its '\n' and a '\r' before
// it) into `line`; returns the position after it.
size_t next_line(std::string_view text, size_t pos, std::string_view& line);

// Splits one line into fields (double-quoted fields may hold commas and "");
// offsets are 1-based character columns. Throws InputError naming
// source:line:column for an unterminated quote or text after one.
void split(std::string_view line, const std::string& source, int line_no,
           std::vector<std::string>& fields, std::vector<int>& offsets);

// Throws InputError naming source:line:column for an empty column name or a
// name that appears twice in a header line split into fields at offsets.
void check_header(const std::vector<std::string>& fields, const std::vector<int>& offsets,
                  const std::string& source, int line_no);

// Throws "source:line:column: row has N fields, the header has M" unless the
// line split at `offsets` has header_size fields.
void check_row_width(std::string_view line, const std::vector<int>& offsets, size_t header_size,
                     const std::string& source, int line_no);

// A cell as a finite number (a leading '+' allowed); InputError
// "source:line:column: column 'name': ..." otherwise.
double cell_number(std::string_view cell, const std::string& source, int line_no, int column,
                   const std::string& name);

}  // namespace massid::detail
