#include "massid/json_text.hpp"

#include <fmt/format.h>

#include "massid/errors.hpp"

namespace massid {

nlohmann::ordered_json parse_json(const std::string& text, const std::string& source) {
  try {
    return nlohmann::ordered_json::parse(text);
  } catch (const nlohmann::ordered_json::parse_error& e) {
    // 1-based line and column of the byte before which parsing failed.
    const size_t byte = e.byte > 0 ? e.byte - 1 : 0;
    int line = 1, col = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    const std::string what = e.what();
    const auto pos = what.find("parse error");
    throw InputError(fmt::format("{}:{}:{}: malformed JSON: {}", source, line, col,
                                 pos == std::string::npos ? what : what.substr(pos)));
  }
}

}  // namespace massid
