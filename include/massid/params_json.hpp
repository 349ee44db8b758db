// Writing a params file (read back by params_file.hpp's read_params).
#pragma once

#include <string>

#include "massid/base_parameters.hpp"
#include "massid/estimation.hpp"
#include "massid/model.hpp"
#include "massid/physical.hpp"

namespace massid {

// JSON text of an identification (values omitted when summary is null, as
// `model --json` prints), with a "physical" section when `physical` is given.
std::string params_json(const Model& model, const BaseParameters& base,
                        const IdentifySummary* summary, const PhysicalSummary* physical = nullptr);

}  // namespace massid
