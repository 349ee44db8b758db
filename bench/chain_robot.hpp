// Serial test chains of any length for the scaling benchmarks: n revolute
// joints alternating about z and y, 0.15 m links, 1 kg each with an offset
// centre of mass, on a 2 kg sensor plate. Written to the temporary directory
// and loaded like any URDF.
#pragma once

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace massid::bench {

inline std::string chain_urdf_text(int joints) {
  std::string x = "<?xml version=\"1.0\"?>\n<robot name=\"chain" + std::to_string(joints) +
                  "\">\n  <link name=\"l0\"><inertial><origin xyz=\"0 0 0.02\"/><mass "
                  "value=\"2\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" "
                  "izz=\"0.01\"/></inertial></link>\n";
  for (int j = 1; j <= joints; ++j) {
    // (fmt, not "l" + std::to_string: GCC 12's -Wrestrict at -O3 misreads
    // operator+(const char*, string&&).)
    const std::string p = fmt::format("l{}", j - 1), c = fmt::format("l{}", j);
    x += "  <joint name=\"j" + std::to_string(j) + "\" type=\"revolute\"><parent link=\"" + p +
         "\"/><child link=\"" + c + "\"/><origin xyz=\"0 0 " + (j == 1 ? "0.05" : "0.15") +
         "\" rpy=\"0 0 0\"/><axis xyz=\"" + (j % 2 ? "0 0 1" : "0 1 0") +
         "\"/><limit lower=\"-3\" upper=\"3\" effort=\"1\" velocity=\"1\"/></joint>\n";
    x += "  <link name=\"" + c +
         "\"><inertial><origin xyz=\"0.02 0.01 0.07\"/><mass value=\"1\"/><inertia ixx=\"0.003\" "
         "ixy=\"0\" ixz=\"0\" iyy=\"0.003\" iyz=\"0\" izz=\"0.001\"/></inertial></link>\n";
  }
  return x + "</robot>\n";
}

inline Model chain_robot(int joints) {
  const auto path =
      std::filesystem::temp_directory_path() / ("massid_chain" + std::to_string(joints) + ".urdf");
  std::ofstream(path) << chain_urdf_text(joints);
  Model model = load_urdf(path.string());
  std::filesystem::remove(path);
  return model;
}

}  // namespace massid::bench
