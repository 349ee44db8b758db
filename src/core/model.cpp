#include "massid/core/model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numbers>

#include "massid/core/errors.hpp"

namespace massid {

double Joint::generic_position(double u) const {
  double lo = -std::numbers::pi, hi = std::numbers::pi;
  if (type == JointType::Prismatic) {
    lo = limited ? lower : -1.0;
    hi = limited ? upper : 1.0;
  }
  return lo + (hi - lo) * u;
}

double Model::nominal_total_mass() const {
  double m = 0.0;
  for (const Link& l : links) m += l.mass;
  return m;
}

int Model::find_link(const std::string& name) const {
  for (int i = 0; i < num_links(); ++i)
    if (links[i].name == name) return i;
  return -1;
}

int Model::find_joint(const std::string& name) const {
  for (int i = 0; i < num_joints(); ++i)
    if (joints[i].name == name) return i;
  return -1;
}

namespace {

// Link l's joint made fixed at position `value` (rad or m): folded into its origin.
void fix_link(Link& link, double value) {
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  if (link.type == JointType::Revolute)
    motion.rotate(Eigen::AngleAxisd(value, link.axis));
  else
    motion.translate(value * link.axis);
  link.origin = link.origin * motion;
  link.type = JointType::Fixed;
  link.joint_index = -1;
  link.joint_scale = 1.0;
  link.joint_offset = 0.0;
}

}  // namespace

Model hold_joints(Model model, const std::vector<std::pair<std::string, double>>& held) {
  for (const auto& hold : held) {
    std::string name = hold.first;  // (not a structured binding: the lambda below captures it)
    double value = hold.second;
    // Holding a mimic joint holds its master where the mimic is at `value`.
    const auto mimic = std::find_if(model.mimics.begin(), model.mimics.end(),
                                    [&](const MimicJoint& m) { return m.name == name; });
    if (mimic != model.mimics.end()) {
      if (mimic->multiplier == 0.0)
        throw InputError(
            fmt::format("{}: mimic joint '{}' does not move with '{}' (multiplier "
                        "0): hold nothing, it is fixed already",
                        model.source, name, mimic->master));
      value = (value - mimic->offset) / mimic->multiplier;
      name = mimic->master;
    }
    const int j = model.find_joint(name);
    if (j < 0)
      throw InputError(fmt::format("{}: '{}' is not a movable joint below the sensor link '{}'",
                                   model.source, name, model.sensor_link()));
    fix_link(model.links[model.joints[j].link], value);
    // Its mimic joints are held too, where they follow it.
    const auto follows = [&](const MimicJoint& m) { return m.master == name; };
    for (const MimicJoint& m : model.mimics)
      if (follows(m)) fix_link(model.links[m.link], m.multiplier * value + m.offset);
    model.mimics.erase(std::remove_if(model.mimics.begin(), model.mimics.end(), follows),
                       model.mimics.end());
    model.joints.erase(model.joints.begin() + j);
    model.held.emplace_back(name, value);
  }
  for (Link& link : model.links)
    if (link.type == JointType::Fixed) link.joint_index = -1;
  for (int j = 0; j < model.num_joints(); ++j) model.links[model.joints[j].link].joint_index = j;
  for (const MimicJoint& m : model.mimics)
    model.links[m.link].joint_index = model.find_joint(m.master);
  return model;
}

Model with_sensor_pose(Model model, SensorPoseColumns pose, bool position) {
  model.upstream.clear();
  model.upstream_joints.clear();
  model.pose = pose;
  if (pose == SensorPoseColumns::None) return model;
  std::vector<const char*> names;
  if (pose == SensorPoseColumns::Quaternion)
    names.assign(std::begin(kPoseQuaternion), std::end(kPoseQuaternion));
  else
    names.assign(std::begin(kPoseMatrix), std::end(kPoseMatrix));
  if (position) names.insert(names.end(), std::begin(kPosePosition), std::end(kPosePosition));
  for (const char* n : names) {
    Joint j;
    j.name = n;
    j.type = JointType::Prismatic;  // a plain number: no _deg column
    j.link = -1;
    j.limited = false;
    model.upstream_joints.push_back(j);
  }
  return model;
}

}  // namespace massid
