// The recorders' spellings of the wrench fx fy fz mx my mz that the tests
// write logs with (test_column_names.cpp, test_cli_columns.cpp): one per row.
#pragma once

#include <string>
#include <vector>

namespace massid_test {

inline const std::vector<std::vector<std::string>> kWrenchSpellings = {
    {"fx", "fy", "fz", "tx", "ty", "tz"},
    {"Fx", "Fy", "Fz", "Tx", "Ty", "Tz"},
    {"force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z"},
    {"field.wrench.force.x", "field.wrench.force.y", "field.wrench.force.z",
     "field.wrench.torque.x", "field.wrench.torque.y", "field.wrench.torque.z"},
    {"/ft_sensor/wrench/force/x", "/ft_sensor/wrench/force/y", "/ft_sensor/wrench/force/z",
     "/ft_sensor/wrench/torque/x", "/ft_sensor/wrench/torque/y", "/ft_sensor/wrench/torque/z"},
    {"wrench.force.x", "wrench.force.y", "wrench.force.z", "wrench.torque.x", "wrench.torque.y",
     "wrench.torque.z"},
};

}  // namespace massid_test
