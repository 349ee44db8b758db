#include "io/json_text.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

#include "massid/core/errors.hpp"

namespace massid {
namespace {

using json = nlohmann::ordered_json;

// The DOM builder of json::parse, but it keeps where and why parsing stopped
// instead of throwing: nlohmann reports a number too large for a double
// ("1e400") as out_of_range, not parse_error, and without a byte position.
struct PositionedDomParser : nlohmann::detail::json_sax_dom_parser<json> {
  explicit PositionedDomParser(json& result)
      : nlohmann::detail::json_sax_dom_parser<json>(result, false) {}
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) {
    error_byte = position;
    error = e.what();
    return false;
  }
  std::size_t error_byte = 0;
  std::string error;
};

}  // namespace

nlohmann::ordered_json parse_json(const std::string& text, const std::string& source) {
  json result;
  PositionedDomParser sax(result);
  if (json::sax_parse(text, &sax)) return result;
  // 1-based line and column of the byte before which parsing failed.
  const std::string_view before =
      std::string_view(text).substr(0, sax.error_byte > 0 ? sax.error_byte - 1 : 0);
  const auto line = 1 + std::count(before.begin(), before.end(), '\n');
  const size_t col = before.size() - (before.rfind('\n') + 1) + 1;  // (npos + 1 == 0)
  // "[json.exception.parse_error.101] parse error at line 1, column 2: ...": from "parse error";
  // "[json.exception.out_of_range.406] number overflow parsing '1e400'": after the tag.
  const std::string& what = sax.error;
  size_t start = what.find("parse error");
  if (start == std::string::npos) {
    const size_t tag = what.find("] ");
    start = tag == std::string::npos ? 0 : tag + 2;
  }
  throw InputError(
      fmt::format("{}:{}:{}: malformed JSON: {}", source, line, col, what.substr(start)));
}

}  // namespace massid
