// Writing a params file (read back by params_file.hpp's read_params).
#pragma once

#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/physical.hpp"

namespace massid {

// JSON text of an identification (values omitted when summary is null, as
// `model --json` prints), with a "physical" section when `physical` is given.
std::string params_json(const Model& model, const BaseParameters& base,
                        const IdentifySummary* summary, const PhysicalSummary* physical = nullptr);

}  // namespace massid
