// Shared helpers of the mimic-joint tests (test_mimic.cpp,
// test_mujoco_plant.cpp).
//
//   gripper_urdf  a small arm with a two-finger gripper whose second finger
//                 mimics the first (revolute) and a prismatic finger that
//                 mimics a prismatic master, all with offsets from the axes so
//                 that every mimic moves mass; without the <mimic> tags the
//                 same robot with five independent joints.
//   expand        the joint vector of that robot without mimic tags for one of
//                 the robot with them, the mimic positions computed here from
//                 the URDF's multipliers and offsets.
#pragma once

#include <Eigen/Core>
#include <iomanip>
#include <locale>
#include <sstream>
#include <string>

#include "massid/core/model.hpp"

namespace massid::test {

// A mimic joint's coefficients: q = multiplier q_master + offset.
struct GripperMimics {
  double finger_multiplier = -1.5, finger_offset = 0.2;  // finger_b follows finger_a
  double slide_multiplier = 0.5, slide_offset = 0.01;    // slide_b follows slide_a
};

inline std::string gripper_urdf(bool with_mimic, const GripperMimics& m = {}) {
  const auto mimic = [&](const char* master, double multiplier, double offset) {
    if (!with_mimic) return std::string();
    std::ostringstream s;
    s.imbue(std::locale::classic());
    s << std::setprecision(17) << "<mimic joint=\"" << master << "\" multiplier=\"" << multiplier
      << "\" offset=\"" << offset << "\"/>";
    return s.str();
  };
  return R"(<robot name="g">
  <link name="base"><inertial><mass value="2"/><origin xyz="0 0 0.05"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="arm"><inertial><mass value="1.5"/><origin xyz="0.1 0.02 0.2"/>
    <inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0" izz="0.01"/></inertial></link>
  <link name="fa"><inertial><mass value="0.3"/><origin xyz="0.03 0.01 0.05"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.001"/></inertial></link>
  <link name="fb"><inertial><mass value="0.25"/><origin xyz="-0.02 0.04 0.06"/>
    <inertia ixx="0.001" ixy="0" ixz="0.0002" iyy="0.001" iyz="0" izz="0.002"/></inertial></link>
  <link name="sa"><inertial><mass value="0.2"/><origin xyz="0.01 0 0.02"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="sb"><inertial><mass value="0.15"/><origin xyz="0 0.02 0.01"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="finger_a" type="revolute"><parent link="arm"/><child link="fa"/>
    <origin xyz="0.1 0 0.3"/><axis xyz="1 0 0"/>
    <limit lower="-0.5" upper="0.6" effort="1" velocity="1"/></joint>
  <joint name="finger_b" type="revolute"><parent link="arm"/><child link="fb"/>
    <origin xyz="0.1 0.05 0.3" rpy="0 0 0.4"/><axis xyz="0.6 0.8 0"/>
    )" + mimic("finger_a", m.finger_multiplier, m.finger_offset) +
         R"(<limit lower="-0.4" upper="1.0" effort="1" velocity="1"/></joint>
  <joint name="slide_a" type="prismatic"><parent link="arm"/><child link="sa"/>
    <origin xyz="0 0.1 0.2"/><axis xyz="0 0 1"/>
    <limit lower="-0.05" upper="0.05" effort="1" velocity="1"/></joint>
  <joint name="slide_b" type="prismatic"><parent link="sa"/><child link="sb"/>
    <origin xyz="0 0.02 0"/><axis xyz="1 0 0"/>
    )" + mimic("slide_a", m.slide_multiplier, m.slide_offset) +
         R"(<limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
</robot>)";
}

// q of the model without mimic joints for q of the model with them (qd, qdd
// with `derivative`: the offset drops out).
inline Eigen::VectorXd expand(const Model& with, const Model& without, const Eigen::VectorXd& q,
                              bool derivative) {
  Eigen::VectorXd out(without.num_joints());
  for (int j = 0; j < without.num_joints(); ++j) {
    const std::string& name = without.joints[j].name;
    const int k = with.find_joint(name);
    if (k >= 0) {
      out[j] = q[k];
      continue;
    }
    for (const MimicJoint& m : with.mimics)
      if (m.name == name)
        out[j] = m.multiplier * q[with.find_joint(m.master)] + (derivative ? 0.0 : m.offset);
  }
  return out;
}

}  // namespace massid::test
