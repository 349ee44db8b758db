// Reading a URDF into a Model (urdfdom): the measured bodies below the sensor
// link, the joints, the links' inertials.
#pragma once

#include <string>

#include "massid/core/model.hpp"

namespace massid {

// Loads a URDF file. `sensor_link` empty means the URDF root link. Throws
// InputError (file:line) for unreadable or malformed files, unsupported joints
// (floating, planar) below the sensor link, a mimic joint whose master is a
// mimic joint too, fixed, or above the sensor link, swapped limits
// (lower > upper), and unknown sensor links (with the closest names).
Model load_urdf(const std::string& path, const std::string& sensor_link = "");
Model load_urdf_string(const std::string& xml, const std::string& sensor_link = "",
                       const std::string& source = "<string>");

}  // namespace massid
