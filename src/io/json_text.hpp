// JSON text with errors that name the file, line and column.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace massid {

// Parses `text` (read from `source`); malformed JSON throws InputError
// "SOURCE:LINE:COL: malformed JSON: ...".
nlohmann::ordered_json parse_json(const std::string& text, const std::string& source);

}  // namespace massid
