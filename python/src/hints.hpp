// The library's hints (massid/core/errors.hpp) spelled as this module's keyword
// arguments, and massid's exceptions raised with them.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/identify/identify_request.hpp"

namespace massid::python {

// One hint as keywords, e.g. {HoldJoints, "a=1 b=2"} -> "fixed={'a': 1, 'b': 2}".
std::string spell(const Hint& hint);

// A setting's keyword alone, e.g. Delay -> "delay".
std::string name(Hint::Setting setting);

// This module's spelling of the request's rules (identify_request.hpp).
SettingSpelling spelling();

// message, then the hints in parentheses: "... (fixed={'elbow': 0.3})".
std::string with_hints(const std::string& message, const std::vector<Hint>& hints);

// InputError and IdentifiabilityError (ValueError subclasses) with the message
// spelled with_hints; each instance also has .message (the library's text)
// and .hints (a list of (setting, value) pairs, e.g. ("fixed", "joint3=0")).
void register_errors(pybind11::module_& m);

}  // namespace massid::python
