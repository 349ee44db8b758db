// The library's hints (errors.hpp) spelled as this CLI's options.
#pragma once

#include <string>
#include <vector>

#include "massid/errors.hpp"

namespace massid::cli {

// One hint as options, e.g. {HoldJoints, "a=1 b=2"} -> "--fixed a=1 --fixed b=2".
std::string spell(const Hint& hint);

// message, then the hints in parentheses: "... hold it at its value (--fixed elbow=0.3)".
std::string with_hints(const std::string& message, const std::vector<Hint>& hints);

}  // namespace massid::cli
