// Gravity in the sensor frame: the standard value and a tilted platform.
#pragma once

#include <Eigen/Core>

namespace massid {

constexpr double kStandardGravity = 9.80665;  // m/s^2

// Platform tilt: rotation about the sensor x axis by `x`, then about the
// (rotated) y axis by `y`, radians: R = Rx(x) Ry(y). Gravity in the tilted
// sensor frame is R^T g_level.
struct Tilt {
  double x = 0.0, y = 0.0;
};

// \param[in] level  (dim 3) gravity in the sensor frame with the platform level, m/s^2
// \return           (dim 3) R^T level, the same gravity in the tilted sensor frame
Eigen::Vector3d tilted_gravity(const Eigen::Vector3d& level, const Tilt& tilt);

// Angle between tilted and level gravity, radians.
double tilt_angle(const Eigen::Vector3d& level, const Tilt& tilt);

}  // namespace massid
