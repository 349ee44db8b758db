// Splitting one CSV line into fields: the rules and messages that the
// whole-file reader (csv_reader.cpp) and the streaming reader (csv_stream.cpp)
// share.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace massid::detail {

// s without leading blanks and trailing blanks or '\r'.
std::string_view trim(std::string_view s);

// Splits one line into fields (double-quoted fields may hold commas and "");
// offsets are 1-based character columns. Throws InputError naming
// source:line:column for an unterminated quote or text after one.
void split(std::string_view line, const std::string& source, int line_no,
           std::vector<std::string>& fields, std::vector<int>& offsets);

}  // namespace massid::detail
