#include "massid/model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <numbers>

#include "massid/errors.hpp"

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

Model hold_joints(Model model, const std::vector<std::pair<std::string, double>>& held) {
  for (const auto& [name, value] : held) {
    const int j = model.find_joint(name);
    if (j < 0)
      throw InputError(fmt::format("{}: '{}' is not a movable joint below the sensor link '{}'",
                                   model.source, name, model.sensor_link()));
    Link& link = model.links[model.joints[j].link];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (link.type == JointType::Revolute)
      motion.rotate(Eigen::AngleAxisd(value, link.axis));
    else
      motion.translate(value * link.axis);
    link.origin = link.origin * motion;
    link.type = JointType::Fixed;
    model.joints.erase(model.joints.begin() + j);
    model.held.emplace_back(name, value);
  }
  for (Link& link : model.links) link.joint_index = -1;
  for (int j = 0; j < model.num_joints(); ++j) model.links[model.joints[j].link].joint_index = j;
  return model;
}

}  // namespace massid
