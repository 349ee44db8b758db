// A wrist sensor with a hand below it (issue 29): ur_like.urdf with a
// five-finger hand of 36 revolute joints fixed to its tool, and static poses
// of the arm's six joints alone (the joints above the sensor link
// wrist_3_link), the way a mobile manipulator's log holds the arm but not the
// fingers. Shared by test_unlogged_joints.cpp and test_cli_unlogged_joints.cpp.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace massid::hand_test {

inline const std::string kHandArmUrdf = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";
inline const char* const kHandSensor = "wrist_3_link";
inline const char* const kHandArmJoints[6] = {"shoulder_pan_joint", "shoulder_lift_joint",
                                              "elbow_joint",        "wrist_1_joint",
                                              "wrist_2_joint",      "wrist_3_joint"};

// One finger joint of the hand and the position it is held at when unlogged:
// 0, or the limit nearest to 0 (every third flexion joint cannot reach 0).
struct HandJoint {
  std::string name;
  double reference;
};

// The hand's 36 joints in the URDF's (depth-first) order: a wrist roll, then
// per finger an abduction and six flexions.
inline std::vector<HandJoint> hand_joints() {
  std::vector<HandJoint> out{{"hand_roll_joint", 0.0}};
  for (const char* f : {"thumb", "index", "middle", "ring", "little"}) {
    out.push_back({fmt::format("hand_{}_abd_joint", f), 0.0});
    for (int k = 1; k <= 6; ++k)
      out.push_back({fmt::format("hand_{}_flex{}_joint", f, k), k % 3 == 0 ? 0.15 : 0.0});
  }
  return out;
}

// ur_like.urdf with the hand under its tool link.
inline std::string hand_urdf_text() {
  std::ifstream in(kHandArmUrdf);
  std::stringstream s;
  s << in.rdbuf();
  std::string xml = s.str();
  const auto link = [](const std::string& name, double mass, double x, double y, double z) {
    return fmt::format(
        "  <link name=\"{}\"><inertial><origin xyz=\"{} {} {}\" rpy=\"0 0 0\"/><mass "
        "value=\"{}\"/><inertia ixx=\"1e-5\" ixy=\"0\" ixz=\"0\" iyy=\"1e-5\" iyz=\"0\" "
        "izz=\"1e-5\"/></inertial></link>\n",
        name, x, y, z, mass);
  };
  const auto joint = [](const std::string& name, const std::string& parent,
                        const std::string& child, const char* axis, double x, double y, double z,
                        double lower, double upper) {
    return fmt::format(
        "  <joint name=\"{}\" type=\"revolute\"><parent link=\"{}\"/><child link=\"{}\"/>"
        "<origin xyz=\"{} {} {}\" rpy=\"0 0 0\"/><axis xyz=\"{}\"/><limit lower=\"{}\" "
        "upper=\"{}\" effort=\"10\" velocity=\"2\"/></joint>\n",
        name, parent, child, x, y, z, axis, lower, upper);
  };
  std::string hand = link("hand_palm", 0.45, 0.01, -0.004, 0.05);
  hand += joint("hand_roll_joint", "tool", "hand_palm", "0 0 1", 0, 0, 0.04, -1.5, 1.5);
  const std::vector<HandJoint> joints = hand_joints();
  int j = 1;
  const char* fingers[5] = {"thumb", "index", "middle", "ring", "little"};
  for (int f = 0; f < 5; ++f) {
    const double y = -0.04 + 0.02 * f;
    std::string parent = "hand_palm";
    for (int k = 0; k < 7; ++k, ++j) {
      const std::string child = fmt::format("hand_{}_{}", fingers[f], k);
      const double lower = joints[j].reference > 0 ? joints[j].reference : -0.3;
      hand += link(child, 0.02 + 0.002 * k, 0.003, 0.001 * (f - 2), 0.012);
      hand += joint(joints[j].name, parent, child, k == 0 ? "1 0 0" : "0 1 0", k == 0 ? 0.02 : 0.0,
                    k == 0 ? y : 0.0, k == 0 ? 0.09 : 0.025, lower, 1.6);
      parent = child;
    }
  }
  xml.insert(xml.rfind("</robot>"), hand);
  return xml;
}

// `n` static poses of the arm (its six joints, no gravity columns: gravity
// from the joints above the sensor), spread over the joints' ranges.
inline std::string hand_arm_plan(int n) {
  std::string out =
      "shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,"
      "wrist_2_joint,wrist_3_joint\n";
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 6; ++k)
      out +=
          fmt::format("{}{:.6f}", k ? "," : "", 1.4 * std::sin(0.37 * (i + 1) * (k + 1) + 0.5 * k));
    out += "\n";
  }
  return out;
}

// `--fixed JOINT=VALUE` for every hand joint, at its reference position.
inline std::vector<std::pair<std::string, double>> hand_held() {
  std::vector<std::pair<std::string, double>> out;
  for (const HandJoint& j : hand_joints()) out.emplace_back(j.name, j.reference);
  return out;
}

}  // namespace massid::hand_test
