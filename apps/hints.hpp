// The library's hints (errors.hpp) spelled as this CLI's options.
#pragma once

#include <string>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/identify/identify_request.hpp"

namespace massid::cli {

// One hint as options, e.g. {HoldJoints, "a=1 b=2"} -> "--fixed a=1 --fixed b=2".
std::string spell(const Hint& hint);

// A setting's option alone, e.g. Delay -> "--delay", Dynamic -> "--dynamic".
std::string name(Hint::Setting setting);

// The CLI's spelling of the request's rules (identify_request.hpp).
SettingSpelling spelling();

// message, then the hints in parentheses: "... hold it at its value (--fixed elbow=0.3)".
std::string with_hints(const std::string& message, const std::vector<Hint>& hints);

}  // namespace massid::cli
