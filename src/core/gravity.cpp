#include "massid/core/gravity.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace massid {

Eigen::Vector3d tilted_gravity(const Eigen::Vector3d& level, const Tilt& t) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(t.x, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(t.y, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  return R.transpose() * level;
}

double tilt_angle(const Eigen::Vector3d& level, const Tilt& t) {
  const Eigen::Vector3d g = tilted_gravity(level, t);
  return std::atan2(g.cross(level).norm(), g.dot(level));
}

}  // namespace massid
