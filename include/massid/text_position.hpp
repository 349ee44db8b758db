// Positions in text files, for error messages that name line and column.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

namespace massid {

// 1-based line and column of a byte offset in `text`.
std::pair<int, int> line_column(const std::string& text, std::size_t byte);

}  // namespace massid
