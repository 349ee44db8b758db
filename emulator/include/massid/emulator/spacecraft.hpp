// Admittance model of a rigid spacecraft: the base the robot arm would be
// mounted on in orbit. The robot pushes on the base through the interface frame
// (the force/torque sensor frame) with the gravity-compensated wrench; the model
// returns how the base would move, which the Stewart platform then reproduces.
//
// Frames:
//   world      inertial frame.
//   body       attached to the spacecraft, origin at its centre of mass (com).
//   interface  attached to the spacecraft where the robot is mounted: the
//              robot's sensor frame. Fixed in the body frame (body_T_interface).
//
// Wrench input, held constant over a step (zero-order hold): w = [f; m] applied
// AT the interface origin, expressed IN the interface frame (f force, m moment
// about the interface origin). With (R_bi, r) = body_T_interface:
//
//   F_world = R_wb R_bi f                      force on the com (world frame)
//   tau_b   = r x (R_bi f) + R_bi m            moment about the com (body frame)
//
// Newton-Euler, com position c and velocity v in world, angular velocity w_b
// in the body frame, orientation q (body -> world, unit quaternion):
//
//   c' = v,   M v' = F_world,   q' = 1/2 q (x) (0, w_b),
//   I w_b' + w_b x I w_b = tau_b.
//
// Compliant base (the paper's "compliant base" case, zero by default = free
// floating): a linear spring-damper between the interface and a fixed anchor,
// the interface's rest pose world_T_anchor. The interface displacement and
// twist expressed in the anchor frame,
//
//   d = [R_wa^T (p_i - p_a); log(R_wa^T R_wi)],   d' ~ [R_wa^T v_i; R_wa^T w_world],
//
// give a restoring wrench at the interface origin -K d - D d' (anchor frame),
// added to the input wrench. log is the rotation vector; the model is exactly
// linear-elastic for small displacements, which is what it is for.
//
// Integration: classical fourth-order Runge-Kutta with the fixed step dt given to
// step() (the control period, typically 1 ms); the quaternion is renormalised at
// the end of each step. step() does not allocate.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "massid/core/predictor.hpp"  // massid::Wrench: fx fy fz mx my mz

namespace massid::emulator {

using Wrench = massid::Wrench;
using Twist = Eigen::Matrix<double, 6, 1>;  // vx vy vz wx wy wz

// Immutable description of the spacecraft. Check it with validate().
struct SpacecraftParameters {
  double mass = 1.0;                                      // kg
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  // kg m^2, about the com, body frame
  // Interface (sensor) frame in the body frame: rotation R_bi and the interface
  // origin r relative to the com, body frame.
  Eigen::Isometry3d body_T_interface = Eigen::Isometry3d::Identity();
  // Compliant base: stiffness K [N/m, N/rad; couplings in mixed units] and
  // damping D on the interface displacement d = [translation; rotation vector]
  // from world_T_anchor, both expressed in the anchor frame. Zero = free floating.
  // Diagonal case: stiffness.diagonal() << kx, ky, kz, krx, kry, krz.
  Eigen::Matrix<double, 6, 6> stiffness = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> damping = Eigen::Matrix<double, 6, 6>::Zero();
  // Rest pose of the interface in the world frame (only used when compliant);
  // usually the interface's initial pose, see state_at_rest().
  Eigen::Isometry3d world_T_anchor = Eigen::Isometry3d::Identity();
};

// Throws InputError unless mass > 0, the inertia is symmetric positive definite
// (and satisfies the triangle inequality of principal moments), and every entry
// is finite.
void validate(const SpacecraftParameters& params);

// The spacecraft's motion.
struct SpacecraftState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // com, world
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // body -> world, unit
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();        // com velocity, world
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       // body frame
};

// Time derivative of the velocities under a wrench (compliance included).
struct SpacecraftAcceleration {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // com acceleration, world
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // d/dt angular_velocity, body frame
};

// The spacecraft at rest with its interface at world_T_interface.
SpacecraftState state_at_rest(const SpacecraftParameters& params,
                              const Eigen::Isometry3d& world_T_interface);

// world_T_body: the com frame in the world frame.
Eigen::Isometry3d body_pose(const SpacecraftState& state);

// world_T_interface: the interface (sensor) frame in the world frame.
Eigen::Isometry3d interface_pose(const SpacecraftParameters& params, const SpacecraftState& state);

// Twist of the interface frame in the world frame: [velocity of the interface
// origin; angular velocity], both world-expressed.
Twist interface_twist(const SpacecraftParameters& params, const SpacecraftState& state);

// Restoring wrench of the compliant base at the interface origin, interface
// frame (zero when stiffness and damping are zero).
Wrench compliance_wrench(const SpacecraftParameters& params, const SpacecraftState& state);

// Accelerations under wrench_interface (interface frame, at the interface
// origin) plus the compliance wrench.
SpacecraftAcceleration acceleration(const SpacecraftParameters& params,
                                    const SpacecraftState& state, const Wrench& wrench_interface);

// Advances state by dt [s] with one classical RK4 step, wrench_interface held
// constant over the step. Renormalises the quaternion. Does not allocate.
void step(const SpacecraftParameters& params, SpacecraftState& state,
          const Wrench& wrench_interface, double dt);

// Linear momentum M v, world frame.
Eigen::Vector3d linear_momentum(const SpacecraftParameters& params, const SpacecraftState& state);

// Angular momentum about the com, world frame: R_wb I w_b.
Eigen::Vector3d angular_momentum(const SpacecraftParameters& params, const SpacecraftState& state);

// Angular momentum about a fixed world point: R_wb I w_b + (c - point) x M v.
Eigen::Vector3d angular_momentum(const SpacecraftParameters& params, const SpacecraftState& state,
                                 const Eigen::Vector3d& point);

// Kinetic energy 1/2 M |v|^2 + 1/2 w_b^T I w_b.
double kinetic_energy(const SpacecraftParameters& params, const SpacecraftState& state);

}  // namespace massid::emulator
