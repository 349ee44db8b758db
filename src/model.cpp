#include "massid/model.hpp"

#include <numbers>

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

}  // namespace massid
